"""The path a controller follows, as a polyline parametrised by arc length.

A planner's :class:`~polynav.planning.path.Path` is a list of points: dense (one per grid cell, from
A*) or sparse (a few long segments, from Theta*). The controller needs three things from it, all in
terms of the arc length ``s`` [m] from the first point:

- where the robot is along it (:meth:`TrackedPath.project`), searching only *forward* from the last
  answer and only over a bounded stretch, so a path that doubles back near itself cannot make the
  robot skip ahead, and a long path costs the same per period as a short one (PythonRobotics'
  ``search_target_index``; Nav2 ``max_robot_pose_search_dist``);
- the carrot (:meth:`TrackedPath.lookahead`): where the path, going forward from the robot's place,
  leaves the circle of lookahead radius around the robot, interpolated inside the segment;
- points sampled along a stretch (:meth:`TrackedPath.points_at`) for the collision check, which
  must not step over an obstacle lying on the middle of a long segment.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

log = logging.getLogger(__name__)

_TIE = 0.05
"""Path stretches this close [m] to being equally near the robot are told apart by heading."""


@dataclass(frozen=True, slots=True, eq=False)
class TrackedPath:
    """Polyline ``points`` (N, 2) [m] without repeated points, and ``cumulative`` arc lengths (N,).

    Build it with :meth:`from_points`.
    """

    points: npt.NDArray[np.float64]
    cumulative: npt.NDArray[np.float64]

    @classmethod
    def from_points(cls, points: npt.ArrayLike) -> TrackedPath:
        """A tracked path through ``points`` (N >= 1), dropping zero-length segments.

        Raises:
            ValueError: no points.
        """
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        if pts.shape[0] == 0:
            raise ValueError("a path needs at least one point")
        if pts.shape[0] > 1:
            step = np.hypot(*np.diff(pts, axis=0).T)
            pts = np.vstack([pts[:1], pts[1:][step > 1e-9]])
        step = np.hypot(*np.diff(pts, axis=0).T) if pts.shape[0] > 1 else np.zeros(0)
        cumulative = np.concatenate(([0.0], np.cumsum(step)))
        return cls(pts, cumulative)

    @property
    def length(self) -> float:
        """Arc length [m] of the whole path."""
        return float(self.cumulative[-1])

    @property
    def end(self) -> tuple[float, float]:
        return (float(self.points[-1, 0]), float(self.points[-1, 1]))

    def point_at(self, s: float) -> tuple[float, float]:
        """The point at arc length ``s`` [m], clamped to the path."""
        p = self.points_at(np.array([s]))
        return (float(p[0, 0]), float(p[0, 1]))

    def points_at(self, s: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Points (M, 2) at arc lengths ``s`` (M,) [m], clamped to the path."""
        if self.points.shape[0] == 1:
            return np.repeat(self.points, len(s), axis=0)
        return np.column_stack(
            (
                np.interp(s, self.cumulative, self.points[:, 0]),
                np.interp(s, self.cumulative, self.points[:, 1]),
            )
        )

    def headings_at(self, s: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Directions [rad] of the segments holding arc lengths ``s`` (M,); 0 for one point.

        A footprint checked along the path faces this way, as a robot following it would.
        """
        if self.points.shape[0] == 1:
            return np.zeros(len(s))
        seg = np.searchsorted(self.cumulative, s, side="right") - 1
        seg = np.clip(seg, 0, self.points.shape[0] - 2)
        d = self.points[seg + 1] - self.points[seg]
        return np.arctan2(d[:, 1], d[:, 0])

    def _segments(self, start: float, stop: float) -> tuple[int, int]:
        """Indices ``i0..i1`` of the segments (from point i to i+1) overlapping [start, stop]."""
        last = self.points.shape[0] - 2
        i0 = int(np.searchsorted(self.cumulative, start, side="right")) - 1
        i1 = int(np.searchsorted(self.cumulative, stop, side="left"))
        return (min(max(i0, 0), last), min(max(i1, i0 + 1), last + 1))

    def project(
        self, x: float, y: float, *, start: float, window: float, heading: float | None = None
    ) -> float:
        """Arc length [m] of the path point nearest to (x, y), within ``[start, start + window]``.

        Only this forward window is searched: the robot's place on the path never moves back,
        and the search cost is bounded by the window, not the path. Where the path passes the
        robot more than once at nearly the same distance (a hairpin whose legs overlap), the
        stretch running in the robot's ``heading`` [rad] is taken: the robot that has turned
        around is on the way back.
        """
        if self.points.shape[0] == 1:
            return 0.0
        i0, i1 = self._segments(start, start + window)
        a = self.points[i0:i1]
        b = self.points[i0 + 1 : i1 + 1]
        s_a = self.cumulative[i0:i1]
        seg = self.cumulative[i0 + 1 : i1 + 1] - s_a
        d = b - a
        t = ((x - a[:, 0]) * d[:, 0] + (y - a[:, 1]) * d[:, 1]) / (seg * seg)
        # Keep the answer inside the window at both ends.
        t_lo = np.clip((start - s_a) / seg, 0.0, 1.0)
        t_hi = np.clip((start + window - s_a) / seg, 0.0, 1.0)
        t = np.clip(t, t_lo, t_hi)
        gap = np.hypot(a[:, 0] + t * d[:, 0] - x, a[:, 1] + t * d[:, 1] - y)
        k = int(np.argmin(gap))
        if heading is not None:
            near = np.flatnonzero(gap <= gap[k] + _TIE)
            if near.size > 1:
                along = d[near, 0] * math.cos(heading) + d[near, 1] * math.sin(heading)
                k = int(near[np.argmax(along / seg[near])])
        return float(s_a[k] + t[k] * seg[k])

    def lookahead(
        self, x: float, y: float, *, start: float, radius: float, window: float
    ) -> tuple[float, float] | None:
        """The carrot: where the path after ``start`` first leaves the circle (x, y, ``radius``).

        Args:
            x: robot position [m].
            y: robot position [m].
            start: the robot's arc length on the path [m] (from :meth:`project`).
            radius: lookahead distance [m].
            window: how far along the path [m] to search.

        Returns:
            The crossing point, interpolated inside its segment; the point at ``start`` when that
            is already outside the circle (the robot is off the path: steer back onto it, as
            Nav2's ``getLookAheadPoint`` does); the last searched point when the path winds inside
            the circle for the whole window; or ``None`` when the rest of the path lies inside
            the circle (the caller steers at the goal itself).
        """
        r2 = radius * radius
        ax, ay = self.point_at(start)
        if (ax - x) ** 2 + (ay - y) ** 2 >= r2:
            return (ax, ay)
        j0 = int(np.searchsorted(self.cumulative, start, side="right"))
        j1 = int(np.searchsorted(self.cumulative, start + window, side="right")) + 1
        ahead = self.points[j0:j1]
        if ahead.shape[0] == 0:
            return None
        outside = np.flatnonzero((ahead[:, 0] - x) ** 2 + (ahead[:, 1] - y) ** 2 >= r2)
        if outside.size == 0:
            if j1 >= self.points.shape[0]:
                return None
            return (float(ahead[-1, 0]), float(ahead[-1, 1]))
        k = int(outside[0])
        if k > 0:
            ax, ay = float(ahead[k - 1, 0]), float(ahead[k - 1, 1])
        bx, by = float(ahead[k, 0]), float(ahead[k, 1])
        return _exit_crossing((ax - x, ay - y), (bx - x, by - y), radius, (x, y))


def _exit_crossing(
    a: tuple[float, float], b: tuple[float, float], radius: float, centre: tuple[float, float]
) -> tuple[float, float]:
    """Where segment a→b (relative to ``centre``, a inside the circle, b outside) leaves it."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    qa = dx * dx + dy * dy
    qb = 2.0 * (a[0] * dx + a[1] * dy)
    qc = a[0] * a[0] + a[1] * a[1] - radius * radius
    disc = max(qb * qb - 4.0 * qa * qc, 0.0)
    t = min(max((-qb + math.sqrt(disc)) / (2.0 * qa), 0.0), 1.0)
    return (centre[0] + a[0] + t * dx, centre[1] + a[1] + t * dy)
