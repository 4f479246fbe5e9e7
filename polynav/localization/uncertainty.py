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

    Dead reckoning runs every control period, so :meth:`predict` and :attr:`uncertainty` work
    on plain floats (the 2x2 position block has a closed-form eigen-decomposition); only a
    match's update, a few times a second, goes through numpy.

    Args:
        min_position: floor of the position's standard deviation [m], > 0.
        min_heading: floor of the heading's standard deviation [rad], > 0.
    """

    def __init__(self, *, min_position: float, min_heading: float) -> None:
        self._min_position = min_position
        self._min_heading = min_heading
        # The symmetric matrix's six entries: xx, xy, yy, xt, yt, tt.
        self._xx = self._yy = min_position**2
        self._tt = min_heading**2
        self._xy = self._xt = self._yt = 0.0
        self._cached: PoseUncertainty | None = None

    @property
    def matrix(self) -> npt.NDArray[np.float64]:
        """The covariance, map frame, ``(x, y, theta)``."""
        return np.array([[self._xx, self._xy, self._xt],
                         [self._xy, self._yy, self._yt],
                         [self._xt, self._yt, self._tt]])

    @property
    def uncertainty(self) -> PoseUncertainty:
        """Standard deviations: position along its worst direction, and heading."""
        if self._cached is None:
            worst, _, _ = _eigen2(self._xx, self._xy, self._yy)
            self._cached = PoseUncertainty(position=math.sqrt(max(worst, 0.0)),
                                           heading=math.sqrt(max(self._tt, 0.0)))
        return self._cached

    def reset(self, position: float, heading: float) -> None:
        """Forget the history: the pose is known to ``position`` [m] and ``heading`` [rad]."""
        self._xx = self._yy = max(position, self._min_position) ** 2
        self._tt = max(heading, self._min_heading) ** 2
        self._xy = self._xt = self._yt = 0.0
        self._cached = None

    def predict(self, distance: float, rotation: float, *, drift: float,
                heading_drift: float) -> None:
        """Dead reckoning over ``distance`` [m] and ``rotation`` [rad] (either sign).

        Each eigen-direction of the position block has its standard deviation widened by
        ``drift * |distance|`` [m], the heading's by ``heading_drift * |rotation|``; the
        correlations between them are kept (the matrix is scaled, ``G P G^T``, not added to).
        """
        grow_xy = drift * abs(distance)
        grow_theta = heading_drift * abs(rotation)
        if grow_xy <= 0.0 and grow_theta <= 0.0:
            return
        floor = self._min_position**2
        big, small, angle = _eigen2(self._xx, self._xy, self._yy)
        s1, s2 = math.sqrt(max(big, floor)), math.sqrt(max(small, floor))
        f1, f2 = (s1 + grow_xy) / s1, (s2 + grow_xy) / s2
        c, s = math.cos(angle), math.sin(angle)
        # G's position block: f1 along (c, s), f2 along (-s, c).
        gxx, gxy, gyy = f1 * c * c + f2 * s * s, (f1 - f2) * c * s, f1 * s * s + f2 * c * c
        heading = math.sqrt(max(self._tt, self._min_heading**2))
        gt = (heading + grow_theta) / heading
        xx, xy, yy, xt, yt = self._xx, self._xy, self._yy, self._xt, self._yt
        # G P: rows of the position block, then G P G^T.
        axx, axy = gxx * xx + gxy * xy, gxx * xy + gxy * yy
        ayx, ayy = gxy * xx + gyy * xy, gxy * xy + gyy * yy
        self._xx = axx * gxx + axy * gxy
        self._xy = axx * gxy + axy * gyy
        self._yy = ayx * gxy + ayy * gyy
        self._xt = (gxx * xt + gxy * yt) * gt
        self._yt = (gxy * xt + gyy * yt) * gt
        self._tt *= gt * gt
        self._cached = None

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
        prior = self.matrix + 1e-12 * np.eye(3)
        posterior = np.linalg.inv(np.linalg.inv(prior) + added)
        self._set(0.5 * (posterior + posterior.T))
        self._apply_floor()

    def add_offset(self, dx: float, dy: float, dtheta: float) -> None:
        """An error of ``(dx, dy, dtheta)`` is known to remain (a clamped correction's rest)."""
        self._xx += dx * dx
        self._xy += dx * dy
        self._yy += dy * dy
        self._xt += dx * dtheta
        self._yt += dy * dtheta
        self._tt += dtheta * dtheta
        self._cached = None

    def _set(self, m: npt.NDArray[np.float64]) -> None:
        self._xx, self._xy, self._xt = float(m[0, 0]), float(m[0, 1]), float(m[0, 2])
        self._yy, self._yt, self._tt = float(m[1, 1]), float(m[1, 2]), float(m[2, 2])
        self._cached = None

    def _apply_floor(self) -> None:
        floor = self._min_position**2
        big, small, angle = _eigen2(self._xx, self._xy, self._yy)
        if small < floor:
            big, small = max(big, floor), floor
            c, s = math.cos(angle), math.sin(angle)
            self._xx = big * c * c + small * s * s
            self._xy = (big - small) * c * s
            self._yy = big * s * s + small * c * c
        self._tt = max(self._tt, self._min_heading**2)
        self._cached = None


def _eigen2(a: float, b: float, c: float) -> tuple[float, float, float]:
    """Eigenvalues (larger, smaller) of ``[[a, b], [b, c]]`` and the larger one's direction
    angle [rad]."""
    mean = 0.5 * (a + c)
    radius = math.hypot(0.5 * (a - c), b)
    return mean + radius, mean - radius, 0.5 * math.atan2(2.0 * b, a - c)
