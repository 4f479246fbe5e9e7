"""The Galileo (bwbot) dialect: HTTP API on 3546, WebSocket topics on 3547, UDP discovery on 22002.

See ``docs/galileo.md`` for pointing a Galileo client at polynav and for every decision the vendor's
spec leaves open.
"""

from __future__ import annotations

from polynav.protocols.galileo.config import GalileoConfig
from polynav.protocols.galileo.server import serve

__all__ = ["GalileoConfig", "serve"]
