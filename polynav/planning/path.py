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
