"""Collision and clearance checks of a footprint swept along poses on a cost grid."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.footprint import kernels
from polynav.footprint.kernels import NO_CELLS, clearance_gaps, first_hit, mask
from polynav.footprint.shape import Footprint
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.interface import CostGrid
from polynav.maps.map import MapInfo


def poses_array(poses: Sequence[Pose2D]) -> npt.NDArray[np.float64]:
    """Poses as an (N, 3) array of x, y, theta, the form the checks take."""
    out = np.empty((len(poses), 3), dtype=np.float64)
    for i, p in enumerate(poses):
        out[i] = (p.x, p.y, p.theta)
    return out


def rotation_poses(
    footprint: Footprint, pose: Pose2D, turn: float, resolution: float
) -> npt.NDArray[np.float64]:
    """Poses (N, 3) of a turn in place by ``turn`` [rad] from ``pose``, both ends included.

    Spaced by :meth:`Footprint.rotation_step`, so checking them checks the whole swept area.
    """
    n = max(int(math.ceil(abs(turn) / footprint.rotation_step(resolution))), 1)
    out = np.empty((n + 1, 3), dtype=np.float64)
    out[:, 0] = pose.x
    out[:, 1] = pose.y
    out[:, 2] = pose.theta + np.linspace(0.0, turn, n + 1)
    return out


def collides(
    footprint: Footprint, costmap: CostGrid, pose: Pose2D, *, unknown_is_lethal: bool = False
) -> bool:
    """True if the footprint at ``pose`` overlaps a LETHAL cell (see the module docstring)."""
    return first_collision(
        footprint, costmap, poses_array([pose]), unknown_is_lethal=unknown_is_lethal
    ) is not None


def first_collision(
    footprint: Footprint,
    costmap: CostGrid,
    poses: npt.NDArray[np.float64],
    *,
    unknown_is_lethal: bool = False,
    ignore_start: bool = False,
) -> int | None:
    """Index of the first pose at which the footprint overlaps a LETHAL cell, or ``None``.

    With ``ignore_start`` the cells the footprint overlaps at the *first* pose do not count
    anywhere along the sequence: a robot touching a mark (wedged, or an estimate a centimetre
    off) may move, but only if it touches nothing new on the way.

    Args:
        footprint: the body.
        costmap: costs ``[iy, ix]`` and their geometry.
        poses: (N, 3) rows of x [m], y [m], theta [rad] in the costmap's world frame, in the
            order the robot reaches them; sample them finely enough (half a cell of travel, see
            :func:`rotation_poses`) that nothing slips between two.
        unknown_is_lethal: treat UNKNOWN cells and cells off the grid as obstacles.
    """
    local = _to_grid_frame(costmap.info, poses)
    grid = np.ascontiguousarray(costmap.costs)
    ignore = NO_CELLS
    if ignore_start and local.shape[0] > 0:
        ignore = kernels.overlapped_cells(grid, costmap.info.resolution, footprint.vertices,
                                          footprint.radius, local[0], unknown_is_lethal)
    hit = first_hit(
        grid,
        costmap.info.resolution,
        footprint.vertices,
        footprint.radius,
        local,
        unknown_is_lethal,
        ignore,
    )
    return None if hit < 0 else int(hit)


def overlapped_cells(footprint: Footprint, costmap: CostGrid, pose: Pose2D
                     ) -> npt.NDArray[np.int64]:
    """The LETHAL cells (K, 2) of ``(ix, iy)`` the footprint overlaps at ``pose``.

    What the body touches where it stands: the cells a closed passage remembers, and those a
    start pose may leave but not touch more of.
    """
    local = _to_grid_frame(costmap.info, poses_array([pose]))
    return np.asarray(kernels.overlapped_cells(
        np.ascontiguousarray(costmap.costs), costmap.info.resolution, footprint.vertices,
        footprint.radius, local[0], False,
    ))


def collision_mask(
    footprint: Footprint,
    costmap: CostGrid,
    poses: npt.NDArray[np.float64],
    *,
    unknown_is_lethal: bool = False,
) -> npt.NDArray[np.bool_]:
    """Per pose (N, 3): does the footprint there overlap a LETHAL cell?"""
    local = _to_grid_frame(costmap.info, poses)
    return mask(
        np.ascontiguousarray(costmap.costs),
        costmap.info.resolution,
        footprint.vertices,
        footprint.radius,
        local,
        unknown_is_lethal,
    )


def clearances(
    footprint: Footprint,
    costmap: CostGrid,
    poses: npt.NDArray[np.float64],
    *,
    horizon: float,
    unknown_is_lethal: bool = False,
) -> npt.NDArray[np.float64]:
    """Gap [m] between the footprint and the nearest LETHAL cell at each pose, up to ``horizon``.

    0 where the footprint overlaps one; ``horizon`` where nothing is nearer. The controller slows
    with this gap rather than stopping for it.
    """
    local = _to_grid_frame(costmap.info, poses)
    return clearance_gaps(
        np.ascontiguousarray(costmap.costs),
        costmap.info.resolution,
        footprint.vertices,
        footprint.radius,
        local,
        float(horizon),
        unknown_is_lethal,
    )


def clearance(
    footprint: Footprint,
    costmap: CostGrid,
    pose: Pose2D,
    *,
    horizon: float,
    unknown_is_lethal: bool = False,
) -> float:
    """:func:`clearances` for one pose."""
    return float(
        clearances(
            footprint,
            costmap,
            poses_array([pose]),
            horizon=horizon,
            unknown_is_lethal=unknown_is_lethal,
        )[0]
    )


def _to_grid_frame(info: MapInfo, poses: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Poses in the grid's own frame (origin at the corner of cell (0, 0), axes along the grid)."""
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    o = info.origin
    c, s = math.cos(o.theta), math.sin(o.theta)
    dx, dy = p[:, 0] - o.x, p[:, 1] - o.y
    out = np.empty_like(p)
    out[:, 0] = c * dx + s * dy
    out[:, 1] = -s * dx + c * dy
    out[:, 2] = p[:, 2] - o.theta
    return out


def warm_up() -> None:
    """Compile the kernels on tiny inputs (the runtime calls this at start-up)."""
    grid = np.zeros((4, 4), dtype=np.uint8)
    grid[1, 1] = costs.LETHAL
    snapshot = _Snapshot(MapInfo(resolution=1.0, width=4, height=4), grid)
    poses = np.array([[2.5, 2.5, 0.0]])
    for fp in (Footprint.circle(0.4), Footprint.rectangle(0.8, 0.6)):
        first_collision(fp, snapshot, poses)
        first_collision(fp, snapshot, poses, ignore_start=True)
        collision_mask(fp, snapshot, poses)
        clearances(fp, snapshot, poses, horizon=1.0)


@dataclass(frozen=True, slots=True, eq=False)
class _Snapshot:
    info: MapInfo
    costs: npt.NDArray[np.uint8]
