"""Re-planning with hysteresis: when does a new route replace the one being driven?

The navigator re-plans every few seconds so that new obstacles are routed round before the
controller must stop for them. In a field of posts two ways round are often nearly equal, and the
costs under them change with every scan: taking whichever is cheaper at each re-plan makes the
route flip between them, and the robot dithers between two gaps for the whole time limit. So the
current route stays unless it is *blocked* (the planner would no longer take it: a cell under its
centre line is INSCRIBED or LETHAL) or the new one is *clearly* shorter: by a fraction of what is
left (``hysteresis``) and by at least ``min_gain`` [m].

"Shorter" is in the time the controller will take, counted as a length (:func:`drive_length`):
it drives at the body's clearance over its ``clearance_time``, so a metre of route through a slot
barely wider than the body takes as long as several in the open. Without a map a route is often
planned through floor not yet seen; when the lidar then shows it a slot the body creeps through,
it is no shorter than the roomy way a re-plan finds beside it, and by length alone the robot kept
it (research-base, lattice course 12 without a map: 1.4 m at 0.2 m/s, 6 s of a 16 s course).
"""

from __future__ import annotations

import logging

import numpy as np

from polynav import footprint as body
from polynav.control import collision
from polynav.control.tracked_path import TrackedPath
from polynav.footprint import Footprint
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


def drive_length(
    costmap: CostGrid,
    footprint: Footprint,
    route: TrackedPath,
    along: float,
    *,
    open_clearance: float,
    least_clearance: float,
) -> float:
    """The route from ``along`` [m] on, as the length [m] the robot would drive in the same
    time in the open.

    The controller drives at full speed where the body has ``open_clearance`` [m] or more to
    the nearest LETHAL cell, and slower in proportion below that, down to the speed of
    ``least_clearance`` [m] (its slowest regulated speed). Each stretch counts its length times
    ``open_clearance`` over the clearance there; ``open_clearance`` 0 counts plain length.
    The body faces along the route, sampled every cell.
    """
    if along >= route.length:
        return 0.0
    if open_clearance <= 0.0:
        return route.length - along
    step = costmap.info.resolution
    s = np.append(np.arange(along, route.length, step), route.length)
    poses = route.poses_at(s)
    gaps = body.clearances(footprint, costmap, poses, horizon=open_clearance)
    slowness = open_clearance / np.clip(gaps, max(least_clearance, 1e-6), open_clearance)
    ds = np.diff(s)
    return float(np.sum(ds * 0.5 * (slowness[:-1] + slowness[1:])))
