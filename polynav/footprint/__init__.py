"""The robot's footprint: the shape of its body in its own frame, and whether it hits anything.

A footprint is a circle (a radius about the base origin) or a simple polygon (vertices in the
base frame, x forward, y left, [m]) that contains the origin. It is the one description of the body
that the simulator, the costmap and the controller share, so that they cannot disagree:

- the costmap inflates obstacles by :attr:`Footprint.inscribed_radius` (a cell closer than this to
  an obstacle is in collision for every heading) and uses :attr:`Footprint.circumscribed_radius`
  as the distance beyond which no heading collides (Nav2 ``calculateMinAndMaxDistances``);
- the controller asks :func:`first_collision` whether the footprint swept along the poses it is
  about to drive touches a LETHAL cell, and :func:`clearance` how far the body is from one.

The collision test is exact for the grid: a LETHAL cell is the full square it covers, and it hits
the footprint when that square and the shape overlap. Only LETHAL cells are obstacles here: the
INSCRIBED band is the costmap's conservative stand-in for a round robot, which is just what an
exact footprint check replaces. UNKNOWN cells and cells off the grid are free unless the caller
says otherwise (the planner decides whether unknown space may be crossed).

The kernels are numba-compiled and look at cell geometry only for the LETHAL cells inside the
footprint's bounding box, so a check costs little more than reading that box.
"""

from polynav.footprint.checks import (
    clearance,
    clearances,
    collides,
    collision_mask,
    first_collision,
    overlapped_cells,
    poses_array,
    rotation_poses,
    warm_up,
)
from polynav.footprint.shape import Footprint

__all__ = [
    "Footprint",
    "clearance",
    "clearances",
    "collides",
    "collision_mask",
    "first_collision",
    "overlapped_cells",
    "poses_array",
    "rotation_poses",
    "warm_up",
]
