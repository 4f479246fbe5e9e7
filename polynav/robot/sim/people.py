"""Simulated people: walkers who follow their :class:`~polynav.worlds.world.PersonRoute` for ever.

A person walks the route's polyline at its speed on simulated time: round the circuit for a
looping route, back and forth for an open one, pausing ``person_pause`` seconds at each end
(at the first waypoint of a circuit). People are dynamic obstacles: the lidar sees them and the
robot collides with them.

People do not steer round the robot, but they are not mindless: a person stands still while
their next step would leave less than ``person_stop_distance`` (0.3 m) of walking along their
heading before contact with the robot, and walks on once the way is clear. So a walker never
runs into the robot or pins it against a wall; any contact is the robot's doing, which is what
the collision record should judge. A person who meets the robot head-on in a corridor waits for
it to make room, as people do. (A person beside the robot, or walking away from it, walks on.)
Nor do they wait for ever: held up ``person_patience`` seconds (the robot stands in a corridor
too narrow to let them by, or keeps stepping back into their way), they turn round and walk their
route the other way, as a person would take the way round rather than stare a robot down. The
hold-ups add up: walking on wears them off at a quarter of the rate they built up, so a robot
that lets a person take two steps and then blocks them again does not start their patience anew.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.worlds.world import PersonRoute

log = logging.getLogger(__name__)

_PATIENCE_RECOVERY = 0.25  # [s of hold-up worn off per s of walking]


class Person:
    """One walker: where they are on their route, and whether they are pausing."""

    def __init__(
        self,
        route: PersonRoute,
        *,
        pause: float,
        stop_distance: float,
        patience: float = math.inf,
    ) -> None:
        self.route = route
        self.radius = route.radius
        self._pause = pause
        self._stop_distance = stop_distance
        self._patience = patience
        self._held = 0.0  # [s] held up by robots, less what walking on has worn off
        wps = [route.waypoints[0]]
        for wp in route.waypoints[1:]:
            if wp != wps[-1]:
                wps.append(wp)
        n = len(wps)
        if route.loop:
            path = [*wps, wps[0]]
            stops = {0, n}
        else:
            path = [*wps, *reversed(wps[:-1])]
            stops = {0, n - 1, len(path) - 1}
        self._path = np.asarray(path, dtype=np.float64)
        seg = np.diff(self._path, axis=0)
        self._lengths = np.hypot(seg[:, 0], seg[:, 1])
        self._dirs = seg / np.where(self._lengths > 0.0, self._lengths, 1.0)[:, None]
        self._stops = stops
        self._mirror()
        self._segment = 0
        self._along = 0.0
        self._pause_left = 0.0
        self._still = len(self._lengths) == 0 or float(self._lengths.sum()) == 0.0
        self.x, self.y = float(self._path[0, 0]), float(self._path[0, 1])

    @property
    def heading(self) -> float:
        """Walking direction [rad]; while pausing, the direction they will walk next."""
        if self._still:
            return 0.0
        d = self._dir_list[self._segment]
        return math.atan2(d[1], d[0])

    @property
    def pose(self) -> Pose2D:
        return Pose2D(self.x, self.y, self.heading)

    def step(self, dt: float, robot: tuple[float, float, float] | None) -> None:
        """Walk for ``dt`` [s], unless the robot (x, y, radius) [m] stands in the way."""
        self.step_among(dt, () if robot is None else (robot,))

    def step_among(self, dt: float, robots: Sequence[tuple[float, float, float]]) -> None:
        """Walk for ``dt`` [s], unless one of the robots (x, y, radius) [m] stands in the way."""
        if self._still:
            return
        if self._pause_left > 0.0:
            used = min(self._pause_left, dt)
            self._pause_left -= used
            dt -= used
            if dt <= 0.0:
                return
        remaining = self.route.speed * dt
        for rx, ry, r_radius in robots:
            if self._blocked_by(rx, ry, r_radius, remaining):
                self._held += dt
                if self._held >= self._patience:
                    self._turn_round()
                return
        self._held = max(0.0, self._held - _PATIENCE_RECOVERY * dt)
        while remaining > 0.0:
            left = self._length_list[self._segment] - self._along
            if remaining < left:
                self._along += remaining
                break
            remaining -= left
            self._segment += 1
            self._along = 0.0
            at_stop = self._segment in self._stops
            if self._segment == len(self._lengths):
                self._segment = 0
            if at_stop and self._pause > 0.0:
                # The time left in this step already counts toward the pause.
                self._pause_left = max(0.0, self._pause - remaining / self.route.speed)
                break
        start = self._path_list[self._segment]
        d = self._dir_list[self._segment]
        self.x = start[0] + self._along * d[0]
        self.y = start[1] + self._along * d[1]

    def _turn_round(self) -> None:
        """Walk the route the other way from here: the same polyline reversed, at the mirrored
        place on it (the pauses stay at the same ends)."""
        self._held = 0.0
        last = len(self._path) - 1
        self._path = self._path[::-1].copy()
        self._lengths = self._lengths[::-1].copy()
        self._dirs = -self._dirs[::-1]
        self._mirror()
        self._stops = {last - i for i in self._stops}
        self._segment = len(self._lengths) - 1 - self._segment
        self._along = float(self._lengths[self._segment]) - self._along
        log.debug("a walker held up by a robot turns round at (%.2f, %.2f)", self.x, self.y)

    def _mirror(self) -> None:
        """Copy the route's arrays into lists of floats, which the per-step arithmetic reads:
        the same IEEE doubles (so the same results), without NumPy's per-element overhead.
        Called wherever the arrays are set."""
        self._path_list: list[list[float]] = self._path.tolist()
        self._length_list: list[float] = self._lengths.tolist()
        self._dir_list: list[list[float]] = self._dirs.tolist()

    def _blocked_by(self, rx: float, ry: float, r_radius: float, step: float) -> bool:
        """Would walking ``step`` and then ``stop_distance`` further touch a disk at (rx, ry)?"""
        d = self._dir_list[self._segment]
        ex, ey = rx - self.x, ry - self.y
        ahead = ex * d[0] + ey * d[1]
        if ahead <= 0.0:
            return False
        lateral = abs(ex * d[1] - ey * d[0])
        reach = self.radius + r_radius
        if lateral >= reach:
            return False
        gap = ahead - math.sqrt(reach * reach - lateral * lateral)
        return bool(gap - step < self._stop_distance)


def as_circles(people: list[Person]) -> npt.NDArray[np.float64]:
    """(K, 3) rows of x, y, radius [m]: the people as the lidar and collision checks see them."""
    out = np.empty((len(people), 3), dtype=np.float64)
    for k, p in enumerate(people):
        out[k, 0], out[k, 1], out[k, 2] = p.x, p.y, p.radius
    return out
