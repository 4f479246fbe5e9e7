"""Whether unknown space is what walls the robot in, when a plan finds no way.

With unknown-as-obstacle on (the costmap's ``track_unknown``, a planner that does not plan
through unknown cells), a robot on a floor mapped only in part can stand in a pocket of known
floor whose every way out runs through grey (unknown) cells its lidar has not seen: behind a
corner, or beyond the lidar's reach. The plan then fails as it does before a wall, but the
cause is different (nothing is in the way that anyone saw; the map is incomplete), and the
dialects tell it apart (Yunji's "trapped in unknown area", 01201). The test: the goal, itself in
known space, is out of the robot's reach over passable cells, and within it were the unknown
cells passable.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.map import MapInfo

_EIGHT = np.ones((3, 3), dtype=bool)  # the planners move to all eight neighbours


def walled_in_by_unknown(grid: npt.NDArray[np.uint8], info: MapInfo, start: Pose2D,
                         goal: Pose2D) -> bool:
    """Whether unknown cells (and only they) part ``start`` from ``goal`` on the costs
    ``grid[iy, ix]``: the goal is known space, unreachable over passable cells (below
    INSCRIBED), reachable were unknown cells passable too."""
    sx, sy = info.world_to_cell(start.x, start.y)
    gx, gy = info.world_to_cell(goal.x, goal.y)
    if not (info.contains(sx, sy) and info.contains(gx, gy)):
        return False
    if int(grid[gy, gx]) == costs.UNKNOWN:
        return False  # a goal in unknown space: unreachable, not a trap
    unknown = grid == costs.UNKNOWN
    passable = grid < costs.INSCRIBED
    open_labels, _ = ndimage.label(passable | unknown, structure=_EIGHT)
    if open_labels[sy, sx] == 0 or open_labels[sy, sx] != open_labels[gy, gx]:
        return False  # walls (or obstacles) part them whatever the unknown cells are
    known_labels, _ = ndimage.label(passable, structure=_EIGHT)
    here = known_labels[sy, sx]
    return bool(here == 0 or here != known_labels[gy, gx])
