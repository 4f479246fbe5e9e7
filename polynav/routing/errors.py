"""Why no route joins two places on different maps."""

from __future__ import annotations

import enum

from polynav.errors import Conflict


class NoRouteReason(enum.Enum):
    """The closed set of reasons a cross-map goal is refused or fails (dialects map these)."""

    NO_LIFT = "no lift serves that floor"
    OUT_OF_SERVICE = "lift out of service"
    UNREACHABLE = "point unreachable"


class NoRoute(Conflict):
    """No route: ``reason`` is the kind, the message says which floor, car or point."""

    def __init__(self, reason: NoRouteReason, message: str) -> None:
        super().__init__(f"{reason.value}: {message}")
        self.reason = reason
        self.detail = message
