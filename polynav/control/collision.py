"""Is the way ahead clear? Costs along the path and along the arc the robot is about to drive.

The costmap is inflated by the robot's inscribed radius, so the robot *centre* collides exactly
where a cell is INSCRIBED or LETHAL: checking points under the centre is a check of the whole
(circular) footprint. Points are sampled at half a cell so no cell along the way is skipped,
whatever the spacing of the planner's points.

UNKNOWN cells and points outside the grid are not obstacles here: the planner decided whether
unknown space may be crossed, and the obstacle layer marks what the lidar sees.
"""

from __future__ import annotations

import logging
import math

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.interface import CostGrid

log = logging.getLogger(__name__)


def costs_at(costmap: CostGrid, points: npt.NDArray[np.float64]) -> npt.NDArray[np.int64]:
    """Costs under ``points`` (N, 2) [m]; UNKNOWN for points outside the grid."""
    info = costmap.info
    cells = info.world_to_cells(points)
    ix, iy = cells[:, 0], cells[:, 1]
    inside = (ix >= 0) & (iy >= 0) & (ix < info.width) & (iy < info.height)
    values = np.full(points.shape[0], costs.UNKNOWN, dtype=np.int64)
    values[inside] = costmap.costs[iy[inside], ix[inside]]
    return values


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
    n = max(int(math.ceil(length / step)), 1)
    s = np.linspace(0.0, length, n + 1)
    if abs(kappa) < 1e-9:
        local_x, local_y = s, np.zeros_like(s)
    else:
        turn = kappa * s
        local_x = np.sin(turn) / kappa
        local_y = (1.0 - np.cos(turn)) / kappa
    c, si = math.cos(pose.theta), math.sin(pose.theta)
    return np.column_stack(
        (pose.x + c * local_x - si * local_y, pose.y + si * local_x + c * local_y)
    )
