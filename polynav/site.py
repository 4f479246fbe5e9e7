"""The site vocabulary shared by every layer: named points and their kinds.

A Site has Floors; a Floor has one Map and named Points. Vendor words (marker, station, target
point) map onto these in their adapters only.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from polynav.geometry import Pose2D


class PointKind(enum.Enum):
    GENERAL = "general"
    CHARGER = "charger"
    INITIAL = "initial"
    FRONT_DESK = "front-desk"
    LIFT_OUTSIDE = "lift-outside"
    LIFT_INSIDE = "lift-inside"
    GATE = "gate"
    CUSTOM = "custom"


@dataclass(frozen=True, slots=True)
class Point:
    """A named pose on one map.

    ``custom_type`` is the site's own type number of a ``CUSTOM`` point (integrators tag their
    points, as Yunji's custom marker types >= 1000); ``None`` otherwise.
    """

    name: str
    map_name: str
    pose: Pose2D
    kind: PointKind = PointKind.GENERAL
    number: int | None = None
    custom_type: int | None = None
