"""The Yunji "Water" chassis dialect: URL-like commands over TCP (port 31001), JSON replies.

See ``docs/yunji.md`` for the framing and the decisions the vendor's spec leaves open.
"""

from __future__ import annotations

from polynav.protocols.yunji.server import YunjiConfig, serve

__all__ = ["YunjiConfig", "serve"]
