"""The Puwei dialect: HTTP and WebSocket on one port (8080), login, tasks, UDP discovery
(``../shared/spec/puwei-api.md``). Adapters translate only (DESIGN §1).

Exports :func:`serve` and :class:`PuweiConfig` (STYLE R4); ``polynav run`` starts the servers
on their own thread (:class:`~polynav.protocols.puwei.server.PuweiThread`).
"""

from __future__ import annotations

from polynav.protocols.puwei.config import PuweiConfig
from polynav.protocols.puwei.server import serve

__all__ = ["PuweiConfig", "serve"]
