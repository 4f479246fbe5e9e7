"""A planned path on one map: a polyline of world points."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt


@dataclass(frozen=True, slots=True, eq=False)
class Path:
    """World points [m] as an (N, 2) float array, start first; ``N >= 1``.

    ``cost`` is the planner's own figure of merit (grid-step length plus cost penalties) in
    metres; ``length`` is the geometric length of the polyline.
    """

    points: npt.NDArray[np.float64]
    cost: float = 0.0

    @property
    def length(self) -> float:
        if self.points.shape[0] < 2:
            return 0.0
        return float(np.sum(np.hypot(*np.diff(self.points, axis=0).T)))

    def __len__(self) -> int:
        return int(self.points.shape[0])

    def crosses(self, p: tuple[float, float], q: tuple[float, float]) -> bool:
        """Whether the polyline crosses (or touches) the segment from ``p`` to ``q``."""
        if self.points.shape[0] < 2:
            return False
        t = leg_crossings(self.points[:-1], self.points[1:], p, q)
        return bool(np.any(~np.isnan(t)))


def leg_crossings(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64],
                  p: tuple[float, float], q: tuple[float, float]) -> npt.NDArray[np.float64]:
    """For each leg from ``a[i]`` to ``b[i]`` (arrays (N, 2)), where along it (0 at ``a[i]``,
    1 at ``b[i]``) it crosses the segment from ``p`` to ``q``; NaN where it does not (parallel
    legs never count)."""
    return segment_crossings(a, b, np.array([p], dtype=np.float64),
                             np.array([q], dtype=np.float64))[:, 0]


def segment_crossings(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64],
                      p: npt.NDArray[np.float64],
                      q: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """:func:`leg_crossings` for many segments at once, from ``p[j]`` to ``q[j]`` (arrays
    (M, 2)): ``t[i, j]`` for leg ``i`` and segment ``j``. One pass over a path's legs for every
    door of a floor, each tick, instead of one per door."""
    r = b - a
    rx, ry = r[:, 0:1], r[:, 1:2]
    sx, sy = q[:, 0] - p[:, 0], q[:, 1] - p[:, 1]
    denom = rx * sy - ry * sx
    qx, qy = p[:, 0] - a[:, 0:1], p[:, 1] - a[:, 1:2]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (qx * sy - qy * sx) / denom
        u = (qx * ry - qy * rx) / denom
    hit = (np.abs(denom) > 1e-12) & (t >= 0.0) & (t <= 1.0) & (u >= 0.0) & (u <= 1.0)
    return np.where(hit, t, np.nan)
