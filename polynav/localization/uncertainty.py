"""The pose's covariance as the tracker goes: grown by dead reckoning, shrunk by scan matches.

A 3x3 covariance of the map pose ``(x, y, theta)`` [m, m, rad]. The tracker's correction is not a
Kalman update (it takes the match along the directions the scan pins and odometry's word along
the others, :mod:`~polynav.localization.degeneracy`), so this is kept beside it in the same terms:

- **Dead reckoning** (:meth:`PoseCovariance.predict`) widens the standard deviation along every
  direction by ``drift`` metres per metre driven, and the heading's by ``heading_drift`` radians
  per radian turned. Linear growth in distance, not a random walk's square root: what dominates
  odometry is a scale and heading error that bends every metre after it, as the tracker's own
  ``odometry_drift`` window already assumes.
- **A scan match** (:meth:`PoseCovariance.correct`) adds the information of its Gauss-Newton
  normal matrix, but only along the directions it constrains (the ones the correction was applied
  along), each endpoint counting as a measurement of ``match_sigma``; the covariance then is the
  inverse of the summed information. Along a corridor nothing is added, and the uncertainty keeps
  growing there while across the corridor it stays at the match's precision.
- What a clamped correction left to the next scans (the tracker moves at most a few centimetres
  per scan) is added as an error still known to be there (:meth:`PoseCovariance.add_offset`).

Floors (``min_position``, ``min_heading``) stand for what the information does not see: a map's
cells, the correlative search's steps, endpoints that are not independent.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from polynav.localization.degeneracy import Constraint
from polynav.localization.interface import PoseUncertainty


class PoseCovariance:
    """The tracker's pose covariance (see the module docstring).

    Args:
        min_position: floor of the position's standard deviation [m], > 0.
        min_heading: floor of the heading's standard deviation [rad], > 0.
    """

    def __init__(self, *, min_position: float, min_heading: float) -> None:
        self._min_position = min_position
        self._min_heading = min_heading
        self._cov: npt.NDArray[np.float64] = np.diag(
            [min_position**2, min_position**2, min_heading**2])

    @property
    def matrix(self) -> npt.NDArray[np.float64]:
        """A copy of the covariance, map frame, ``(x, y, theta)``."""
        return self._cov.copy()

    @property
    def uncertainty(self) -> PoseUncertainty:
        """Standard deviations: position along its worst direction, and heading."""
        worst = float(np.linalg.eigvalsh(self._cov[:2, :2])[-1])
        return PoseUncertainty(position=math.sqrt(max(worst, 0.0)),
                               heading=math.sqrt(max(float(self._cov[2, 2]), 0.0)))

    def reset(self, position: float, heading: float) -> None:
        """Forget the history: the pose is known to ``position`` [m] and ``heading`` [rad]."""
        self._cov = np.diag([max(position, self._min_position) ** 2,
                             max(position, self._min_position) ** 2,
                             max(heading, self._min_heading) ** 2])

    def predict(self, distance: float, rotation: float, *, drift: float,
                heading_drift: float) -> None:
        """Dead reckoning over ``distance`` [m] and ``rotation`` [rad] (either sign).

        Each eigen-direction of the position block has its standard deviation widened by
        ``drift * |distance|`` [m], the heading's by ``heading_drift * |rotation|``; the
        correlations between them are kept (the matrix is scaled, not added to).
        """
        grow_xy = drift * abs(distance)
        grow_theta = heading_drift * abs(rotation)
        if grow_xy <= 0.0 and grow_theta <= 0.0:
            return
        values, vectors = np.linalg.eigh(self._cov[:2, :2])
        stds = np.sqrt(np.maximum(values, self._min_position**2))
        g = np.eye(3)
        g[:2, :2] = vectors @ np.diag((stds + grow_xy) / stds) @ vectors.T
        heading = math.sqrt(max(float(self._cov[2, 2]), self._min_heading**2))
        g[2, 2] = (heading + grow_theta) / heading
        self._cov = g @ self._cov @ g.T

    def correct(self, constraint: Constraint, *, match_sigma: float) -> None:
        """Add a match's information along the directions it constrains.

        Args:
            constraint: the eigen-analysis of the match's normal matrix; only its constrained
                directions add information.
            match_sigma: the error one endpoint's surface distance stands for [m].
        """
        kept = constraint.constrained
        if not kept.any():
            return
        v = constraint.eigenvectors[:, kept]
        scaled = v @ np.diag(constraint.eigenvalues[kept]) @ v.T / match_sigma**2
        # Back from the scaled space (x, y, length_scale * theta) to (x, y, theta).
        d = np.diag([1.0, 1.0, constraint.length_scale])
        added = d @ scaled @ d
        floor = np.diag([self._min_position**2, self._min_position**2, self._min_heading**2])
        prior = self._cov + 1e-12 * np.eye(3)
        posterior = np.linalg.inv(np.linalg.inv(prior) + added)
        self._cov = 0.5 * (posterior + posterior.T)
        self._apply_floor(floor)

    def add_offset(self, dx: float, dy: float, dtheta: float) -> None:
        """An error of ``(dx, dy, dtheta)`` is known to remain (a clamped correction's rest)."""
        r = np.array([dx, dy, dtheta])
        self._cov = self._cov + np.outer(r, r)

    def _apply_floor(self, floor: npt.NDArray[np.float64]) -> None:
        values, vectors = np.linalg.eigh(self._cov[:2, :2])
        values = np.maximum(values, floor[0, 0])
        self._cov[:2, :2] = vectors @ np.diag(values) @ vectors.T
        self._cov[2, 2] = max(float(self._cov[2, 2]), float(floor[2, 2]))
