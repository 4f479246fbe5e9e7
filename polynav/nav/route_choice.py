"""Re-planning with hysteresis: when does a new route replace the one being driven?

The navigator re-plans every few seconds so that new obstacles are routed round before the
controller must stop for them. In a field of posts two ways round are often nearly equal, and the
costs under them change with every scan: taking whichever is cheaper at each re-plan makes the
route flip between them, and the robot dithers between two gaps for the whole time limit. So the
current route stays unless it is *blocked* (the planner would no longer take it: a cell under its
centre line is INSCRIBED or LETHAL) or the new one is *clearly* shorter: by a fraction of what is
left (``hysteresis``) and by at least ``min_gain`` [m].
"""

from __future__ import annotations

import logging

import numpy as np

from polynav.control import collision
from polynav.control.tracked_path import TrackedPath
from polynav.maps.interface import CostGrid

log = logging.getLogger(__name__)

CLOSED_ROUTE_PLACE = 0.5
"""[m] a route the lidar closed is re-planned at once (or steered round when the controller
stops for it) once per place: this near a place done so before, it waits for the periodic
re-plan or the block's usual course."""


def route_blocked(costmap: CostGrid, route: TrackedPath, along: float) -> bool:
    """Does the route from arc length ``along`` [m] on cross INSCRIBED or LETHAL cells?

    Sampled at half a cell. A stretch the robot starts in does not count: it is driving out.
    """
    return first_blocked(costmap, route, along) is not None


def first_blocked(
    costmap: CostGrid, route: TrackedPath, along: float
) -> tuple[float, float] | None:
    """The first point (x, y) [m] where the route from ``along`` on crosses an INSCRIBED or
    LETHAL cell (as :func:`route_blocked`), or ``None``."""
    step = 0.5 * costmap.info.resolution
    s = np.arange(along, route.length + step, step)
    points = route.points_at(s)
    hit = collision.first_collision(collision.costs_at(costmap, points))
    return None if hit is None else (float(points[hit, 0]), float(points[hit, 1]))


def clearly_shorter(
    *, remaining: float, new_length: float, hysteresis: float, min_gain: float
) -> bool:
    """Is a new route of ``new_length`` [m] worth leaving an unblocked one with ``remaining``
    [m] to go? Only if shorter by ``hysteresis`` of ``remaining`` and by at least ``min_gain``
    [m]."""
    return remaining - new_length >= max(hysteresis * remaining, min_gain)
