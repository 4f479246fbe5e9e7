"""POST /api/navigation/mapless: navigate with no map, goals as poses in the odometry frame.

After it, ``POST /api/navigation/goal`` with a pose (and no map, or map ``odom``) drives there,
with the same events and status as navigation on a map; ``POST /api/navigation/stop`` ends it.
"""

from __future__ import annotations

import logging

from fastapi import APIRouter

from polynav.api.deps import RuntimeDep
from polynav.api.errors import STATE
from polynav.api.schemas import Ok

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/navigation", tags=["navigation"], responses=STATE)


@router.post("/mapless", operation_id="start_mapless_navigation", response_model=Ok)
def start_mapless_navigation(runtime: RuntimeDep) -> Ok:
    """Navigate without a map from where the robot stands: the map is ``odom``, goals are
    poses in the odometry frame, the costmap is built from the lidar as the robot goes (409
    while mapping or busy)."""
    runtime.start_mapless()
    return Ok()
