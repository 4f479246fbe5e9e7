"""The fleet as ``GET /api/fleet`` shows it: one entry per robot of the building.

The composition that runs several robots (:mod:`polynav.house.building`) builds these from
each robot's last state message and hands ``create_app(fleet=...)`` a function listing them; the
API only shows them, so it imports nothing of the fleet layer.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from polynav.geometry import Pose2D

OrderState = Literal["none", "running", "succeeded", "failed"]


@dataclass(frozen=True, slots=True)
class FleetEntry:
    """One robot as ``GET /api/fleet`` lists it."""

    robot_id: str
    ports: dict[str, int]
    floor: str | None
    map_name: str | None
    pose: Pose2D | None
    mode: str
    navigation_state: str
    order_id: str
    order_state: OrderState
    waiting_for: str | None
    zones: tuple[str, ...]
    battery_percent: float
    stamp: float | None = None
    errors: tuple[str, ...] = field(default=())
