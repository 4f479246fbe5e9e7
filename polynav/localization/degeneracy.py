"""Which directions of a pose a scan match constrains, and a correction restricted to them.

A scan matched in a corridor pins the robot across the corridor and in heading, but says
nothing about where along it the robot is: every pose slid along the walls fits as well. The
correlative search still returns *a* pose there (the prior's, or noise's, favourite), and taking
its along-corridor component as a correction is a random walk that the odometry does not make.
After Zhang, Kaess and Singh, "On Degeneracy of Optimization-based State Estimation Problems"
(ICRA 2016), the answer is to look at the match's Gauss-Newton normal matrix

    H = sum_k J_k^T J_k,   J_k = d(surface distance of endpoint k) / d(x, y, theta),

and to apply the correction only along its well constrained eigen-directions, leaving the others
to odometry and IMU.

Units. The translation columns of ``J_k`` are the surface normal at the endpoint (unit vectors),
so ``H``'s translation block counts *endpoints' worth* of surface facing each direction: in a
corridor along x it is about ``[[0, 0], [0, N]]``. The heading column is the endpoint's lever
arm [m]; to compare it with translations, heading is scaled by ``length_scale`` (a rotation by
one radian counts as a translation of ``length_scale`` metres), and every eigenvalue then reads
as endpoints' worth of information along its direction. A direction is *constrained* when its
eigenvalue reaches ``min_information``.

No endpoint, a few on one pillar, one straight wall, a corridor, an open hall: each of these
comes out as the directions it really pins, with no special case.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D, angle_diff, wrap_angle


@dataclass(frozen=True, slots=True, eq=False)
class Constraint:
    """The directions a match pins, in the scaled pose space ``(x, y, length_scale * theta)``.

    Attributes:
        information: the normal matrix ``H`` (3x3) in the map frame, heading unscaled: x and y in
            endpoints per m² (unitless counts), heading in m² per rad² (lever arms squared).
        eigenvalues: eigenvalues of the scaled ``H``, ascending [endpoints].
        eigenvectors: matching unit eigenvectors, as columns (3x3), scaled space.
        constrained: per eigenvector, whether its eigenvalue reaches ``min_information``.
        length_scale: metres one radian of heading counts as [m].
    """

    information: npt.NDArray[np.float64]
    eigenvalues: npt.NDArray[np.float64]
    eigenvectors: npt.NDArray[np.float64]
    constrained: npt.NDArray[np.bool_]
    length_scale: float

    @property
    def degenerate(self) -> bool:
        """True when at least one direction is not constrained."""
        return not bool(self.constrained.all())

    @property
    def heading_constrained(self) -> bool:
        """True when the constrained directions fix heading (a rotation in place is pinned)."""
        return self.fraction_constrained(np.array([0.0, 0.0, 1.0])) > 0.9

    def fraction_constrained(self, direction: npt.NDArray[np.float64]) -> float:
        """How much of ``direction`` (scaled space, any length) lies in the constrained span,
        in [0, 1]: 1 for a direction the scan pins, 0 for one it says nothing about."""
        d = np.asarray(direction, dtype=np.float64)
        norm = float(np.linalg.norm(d))
        if norm == 0.0:
            return 1.0
        v = self.eigenvectors[:, self.constrained]
        return float(np.sum((v.T @ (d / norm)) ** 2))

    def unconstrained_directions(self) -> list[npt.NDArray[np.float64]]:
        """Unit vectors (scaled space) of the directions the scan does not pin."""
        return [self.eigenvectors[:, i].copy() for i in range(3) if not self.constrained[i]]

    def project(self, start: Pose2D, target: Pose2D) -> Pose2D:
        """``target`` with the step from ``start`` kept only along the constrained directions.

        Along an unconstrained direction the result stays where ``start`` is (odometry's word
        holds); along a constrained one it goes to ``target`` (the scan's word holds).
        """
        s = self.length_scale
        delta = np.array([target.x - start.x, target.y - start.y,
                          s * angle_diff(target.theta, start.theta)])
        v = self.eigenvectors[:, self.constrained]
        kept = v @ (v.T @ delta)
        return Pose2D(start.x + float(kept[0]), start.y + float(kept[1]),
                      wrap_angle(start.theta + float(kept[2]) / s))


def constraint(
    information: npt.NDArray[np.float64], *, length_scale: float, min_information: float
) -> Constraint:
    """Eigen-analyse a match's normal matrix (see the module docstring).

    Args:
        information: ``H`` (3x3), map frame, heading in radians.
        length_scale: metres one radian of heading counts as [m], > 0.
        min_information: endpoints' worth of information a direction needs to count as
            constrained.
    """
    h = np.asarray(information, dtype=np.float64).reshape(3, 3)
    scale = np.array([1.0, 1.0, 1.0 / length_scale])
    scaled = h * scale[:, None] * scale[None, :]
    values, vectors = np.linalg.eigh(0.5 * (scaled + scaled.T))
    return Constraint(
        information=h,
        eigenvalues=values,
        eigenvectors=vectors,
        constrained=values >= min_information,
        length_scale=float(length_scale),
    )
