"""``/api/robots``: every robot of the fleet with its live state."""

from __future__ import annotations

from fastapi import APIRouter, Path

from polynav.fleet_api.deps import ManagerDep
from polynav.fleet_api.errors import errors
from polynav.fleet_api.schemas import RobotOut

router = APIRouter(prefix="/api/robots", tags=["robots"])


@router.get("", response_model=list[RobotOut])
def list_robots(manager: ManagerDep) -> list[RobotOut]:
    """Every robot the fleet manager has heard of, by serial number."""
    return [RobotOut.from_domain(view) for view in manager.robots()]


@router.get("/{serial}", response_model=RobotOut,
            responses=errors({404: "no such robot (code `not_found`)"}))
def get_robot(manager: ManagerDep,
              serial: str = Path(min_length=1, max_length=200)) -> RobotOut:
    """One robot."""
    return RobotOut.from_domain(manager.robot(serial))
