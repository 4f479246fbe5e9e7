"""GET /api/fleet: every robot in the building, from any robot's API.

In a building (``polynav run --robots N``) the app is given the building's fleet listing
(:meth:`polynav.house.building.Building.entries`, built from each robot's last state message);
a lone robot lists itself from its own snapshot.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence

from fastapi import APIRouter, Request

from polynav.api.deps import RuntimeDep
from polynav.api.fleet_listing import FleetEntry
from polynav.api.schemas import FleetOut, FleetRobotOut, PoseOut

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api", tags=["fleet"])

FleetListing = Callable[[], Sequence[FleetEntry]]
"""What ``create_app(fleet=...)`` takes: the building's robots as of now."""


@router.get("/fleet", operation_id="get_fleet", response_model=FleetOut,
            summary="Every robot in the building")
def get_fleet(request: Request, runtime: RuntimeDep) -> FleetOut:
    """Each robot with its ports, floor, map, pose, mode, navigation and order state, and the
    traffic zones it holds or waits for."""
    listing: FleetListing | None = getattr(request.app.state, "fleet", None)
    if listing is not None:
        return FleetOut(robots=[_robot(entry) for entry in listing()])
    status = runtime.status()
    port = request.url.port
    return FleetOut(robots=[FleetRobotOut(
        robot_id="robot1", ports={"native": port} if port is not None else {},
        floor=status.floor, map=status.map, pose=PoseOut.from_domain(status.pose),
        mode=status.mode, navigation_state=status.navigation_state, order_id="",
        order_state="none", waiting_for=None, zones=[], battery_percent=status.battery_percent,
        errors=[],
    )])


def _robot(entry: FleetEntry) -> FleetRobotOut:
    return FleetRobotOut(
        robot_id=entry.robot_id, ports=entry.ports, floor=entry.floor, map=entry.map_name,
        pose=PoseOut.from_domain(entry.pose) if entry.pose is not None else None,
        mode=entry.mode, navigation_state=entry.navigation_state, order_id=entry.order_id,
        order_state=entry.order_state,
        waiting_for=entry.waiting_for, zones=list(entry.zones),
        battery_percent=entry.battery_percent, errors=list(entry.errors),
    )
