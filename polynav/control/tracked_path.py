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
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.control import path_kernels as kernels

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
        return self.poses_at(s)[:, :2]

    def headings_at(self, s: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Directions [rad] of the segments holding arc lengths ``s`` (M,); 0 for one point.

        A footprint checked along the path faces this way, as a robot following it would.
        """
        if self.points.shape[0] == 1:
            return np.zeros(len(s))
        return self.poses_at(s)[:, 2]

    def poses_at(self, s: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Poses (M, 3) at arc lengths ``s`` (M,) [m]: :meth:`points_at` and :meth:`headings_at`
        in one pass (the controller wants both, every period)."""
        if self.points.shape[0] == 1:
            out = np.zeros((len(s), 3))
            out[:, :2] = self.points[0]
            return out
        return kernels.sample(self.points, self.cumulative, np.asarray(s, dtype=np.float64))

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
        return float(kernels.project(
            self.points, self.cumulative, float(x), float(y), float(start), float(window),
            heading is not None, 0.0 if heading is None else float(heading), _TIE,
        ))

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
        if self.points.shape[0] == 1:
            ax, ay = self.end
            return (ax, ay) if (ax - x) ** 2 + (ay - y) ** 2 >= radius * radius else None
        found, cx, cy = kernels.lookahead(
            self.points, self.cumulative, float(x), float(y), float(start), float(radius),
            float(window),
        )
        return (cx, cy) if found else None
