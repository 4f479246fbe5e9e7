"""Is the way ahead clear? Costs along the path and along the arc the robot is about to drive.

Two kinds of check live here. Cost lookups under points (:func:`costs_at`) read the inflated
costmap, where the robot *centre* collides where a cell is INSCRIBED or LETHAL: exact for a round
robot of the inscribed radius, and what the proximity regulation reads. Footprint checks
(:func:`first_footprint_collision` over :func:`arc_poses`, ``TrackedPath.poses_at`` or a turn in
place) place the robot's real body, circle or polygon, at each pose and test it against LETHAL cells
(:mod:`polynav.footprint`): a rectangle may pass a gap lengthwise that its circumscribed circle
could not, and turning on the spot sweeps its corners, not a point. Poses are sampled at half a
cell so no cell along the way is skipped, whatever the spacing of the planner's points.

UNKNOWN cells and points outside the grid are not obstacles here: the planner decided whether
unknown space may be crossed, and the obstacle layer marks what the lidar sees.
"""

from __future__ import annotations

import logging
import math

import numba
import numpy as np
import numpy.typing as npt

from polynav import footprint as body
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.interface import CostGrid

log = logging.getLogger(__name__)


def costs_at(costmap: CostGrid, points: npt.NDArray[np.float64]) -> npt.NDArray[np.int64]:
    """Costs under ``points`` (N, 2) [m]; UNKNOWN for points outside the grid."""
    info = costmap.info
    theta = info.origin.theta
    return _costs_at(
        costmap.costs, info.origin.x, info.origin.y, math.cos(theta), math.sin(theta),
        info.resolution, np.asarray(points, dtype=np.float64).reshape(-1, 2),
    )


@numba.njit(cache=True, nogil=True)
def _costs_at(
    grid: npt.NDArray[np.uint8],
    ox: float,
    oy: float,
    c: float,
    s: float,
    resolution: float,
    points: npt.NDArray[np.float64],
) -> npt.NDArray[np.int64]:
    """:func:`costs_at` in one pass, with ``MapInfo.world_to_cells``' arithmetic."""
    height, width = grid.shape
    out = np.empty(points.shape[0], dtype=np.int64)
    for k in range(points.shape[0]):
        dx = points[k, 0] - ox
        dy = points[k, 1] - oy
        ix = int(math.floor((c * dx + s * dy) / resolution))
        iy = int(math.floor((-s * dx + c * dy) / resolution))
        if 0 <= ix < width and 0 <= iy < height:
            out[k] = grid[iy, ix]
        else:
            out[k] = costs.UNKNOWN
    return out


def cost_at(costmap: CostGrid, x: float, y: float) -> int:
    """Cost under the world point (x, y) [m]; UNKNOWN outside the grid."""
    ix, iy = costmap.info.world_to_cell(x, y)
    if not costmap.info.contains(ix, iy):
        return costs.UNKNOWN
    return int(costmap.costs[iy, ix])


def first_collision(values: npt.NDArray[np.int64]) -> int | None:
    """Index of the first colliding cost (INSCRIBED or LETHAL) in a run of samples, or ``None``.

    A run that *starts* in collision (the robot pushed against a wall, a person who walked into
    it, an estimate a few centimetres off) is skipped up to its first clear sample: the robot must
    be allowed to drive out of it, and stopping for the cell it is in would trap it there.
    """
    hit = (values == costs.INSCRIBED) | (values == costs.LETHAL)
    if hit.size and hit[0]:
        clear = np.flatnonzero(~hit)
        if clear.size == 0:
            return None
        hit[: clear[0]] = False
    found = np.flatnonzero(hit)
    return int(found[0]) if found.size else None


def arc_points(pose: Pose2D, kappa: float, length: float, step: float) -> npt.NDArray[np.float64]:
    """Points (N, 2) every ``step`` [m] along the arc of curvature ``kappa`` [1/m] from ``pose``.

    The first point is the robot's own position; the last is at arc length ``length`` [m].
    """
    return arc_poses(pose, kappa, length, step)[:, :2]


def arc_poses(pose: Pose2D, kappa: float, length: float, step: float) -> npt.NDArray[np.float64]:
    """Poses (N, 3) every ``step`` [m] along the arc of :func:`arc_points`, heading included."""
    n = max(int(math.ceil(length / step)), 1)
    return _arc(float(pose.x), float(pose.y), float(pose.theta), float(kappa), float(length), n)


@numba.njit(cache=True, nogil=True)
def _arc(
    x: float, y: float, theta: float, kappa: float, length: float, n: int
) -> npt.NDArray[np.float64]:
    """``n + 1`` poses at arc lengths spaced as ``np.linspace(0, length, n + 1)``: one pass
    instead of a dozen array operations, twice per control period."""
    out = np.empty((n + 1, 3), dtype=np.float64)
    c, si = math.cos(theta), math.sin(theta)
    spacing = length / n
    straight = abs(kappa) < 1e-9
    for k in range(n + 1):
        s = length if k == n else k * spacing
        if straight:
            local_x, local_y = s, 0.0
        else:
            turn = kappa * s
            local_x = math.sin(turn) / kappa
            local_y = (1.0 - math.cos(turn)) / kappa
        out[k, 0] = x + c * local_x - si * local_y
        out[k, 1] = y + si * local_x + c * local_y
        out[k, 2] = theta + kappa * s
    return out


def warm_up() -> None:
    """Compile (or load from numba's cache) the arc and cost kernels, for writable and
    read-only grids (a costmap hands out a read-only view)."""
    _arc(0.0, 0.0, 0.0, 0.5, 1.0, 4)
    grid = np.zeros((2, 2), dtype=np.uint8)
    points = np.array([[0.5, 0.5], [3.0, 0.5]])
    _costs_at(grid, 0.0, 0.0, 1.0, 0.0, 1.0, points)
    grid.flags.writeable = False
    _costs_at(grid, 0.0, 0.0, 1.0, 0.0, 1.0, points)


def first_footprint_collision(
    footprint: Footprint, costmap: CostGrid, poses: npt.NDArray[np.float64]
) -> int | None:
    """Index of the first pose where the body overlaps a LETHAL cell, or ``None``.

    The cells the body already overlaps at the first pose do not count: a robot touching a mark
    (a wedged robot, an estimate a centimetre off) may still move, but only if it touches
    nothing new on the way. (Skipping the whole first run of colliding poses, as
    :func:`first_collision` does for costs under the centre, would let a robot touching one
    post sweep through its neighbour.)
    """
    return body.first_collision(footprint, costmap, poses, ignore_start=True)


def turn_collides(
    footprint: Footprint, costmap: CostGrid, pose: Pose2D, turn: float
) -> bool:
    """Does turning in place by ``turn`` [rad] from ``pose`` sweep the body into a LETHAL cell?

    A circle centred on the base never changes as it turns: only a polygon can.
    """
    if footprint.is_circle or turn == 0.0:
        return False
    poses = body.rotation_poses(footprint, pose, turn, costmap.info.resolution)
    return first_footprint_collision(footprint, costmap, poses) is not None
