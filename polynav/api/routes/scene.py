"""GET /api/scene: the live things a map view draws beside the status (scan, plan, people).

The status snapshot (``GET /api/status`` and the WebSocket) says where the robot is; a map view
also wants what it sees and where it is going. These are read together between the runtime's
ticks, so the scan is drawn from the pose it was taken at, never a half-updated one.
"""

from __future__ import annotations

import logging

import numpy as np
import numpy.typing as npt
from fastapi import APIRouter

from polynav.api.deps import RuntimeDep
from polynav.api.schemas import PoseOut
from polynav.api.schemas_console import SceneOut
from polynav.errors import Conflict
from polynav.geometry import Pose2D
from polynav.robot.interface import LaserScan
from polynav.runtime.site_queries import scan_points

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api", tags=["status"])

#: Most scan points and path points sent: enough to draw, bounded per request.
MAX_SCAN_POINTS = 720
MAX_PATH_POINTS = 500
#: Significant digits kept: millimetres are plenty for a drawing.
DECIMALS = 3


def _rounded(points: npt.NDArray[np.float64]) -> list[list[float]]:
    return [[float(x), float(y)] for x, y in np.round(points, DECIMALS)]


@router.get("/scene", operation_id="get_scene", response_model=SceneOut,
            summary="The live scan, the planned path and the people, for a map view")
def get_scene(runtime: RuntimeDep) -> SceneOut:
    """The robot's newest lidar returns and its running plan, in the frame of its map, and the
    people walking on its floor (the simulator's; none on a real robot)."""

    def read() -> tuple[str | None, float, Pose2D, LaserScan | None, tuple[Pose2D, ...]]:
        status = runtime.status()
        people: tuple[Pose2D, ...] = ()
        if runtime.is_simulated:
            try:
                people = runtime.simulation.people_poses()
            except Conflict:
                people = ()
        return status.map, status.stamp, status.pose, runtime.robot.read_scan(), people

    map_name, stamp, pose, scan, people = runtime.run_between_ticks(read)
    scan_out: list[list[float]] = []
    if scan is not None:
        points = scan_points(scan, pose)
        if len(points) > MAX_SCAN_POINTS:
            points = points[:: -(-len(points) // MAX_SCAN_POINTS)]
        scan_out = _rounded(points)
    path = runtime.queries.planned_path(MAX_PATH_POINTS)
    return SceneOut(
        map=map_name, stamp=stamp, pose=PoseOut.from_domain(pose), scan=scan_out,
        path=[[round(x, DECIMALS), round(y, DECIMALS)] for x, y in path],
        people=[PoseOut.from_domain(p) for p in people],
    )
