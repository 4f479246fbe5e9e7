"""A 2-D pose graph and its sparse, robust least-squares optimisation.

Nodes are robot poses (x, y, theta) in the map frame; an edge ``(i, j, z)`` says that node ``j``
seen from node ``i`` is at ``z`` (``x_i⁻¹ ⊕ x_j ≈ z``), with a standard deviation per
component. The residual of an edge is ``z⁻¹ ⊕ (x_i⁻¹ ⊕ x_j)`` divided by those deviations
(Grisetti et al., "A Tutorial on Graph-Based SLAM", 2010, §IV, in the SE(2) form). Node 0 is
held fixed, which removes the gauge freedom.

:func:`optimize` hands the stacked residuals to ``scipy.optimize.least_squares`` (trust region
reflective with LSMR) with an analytic sparse Jacobian: each edge's three rows touch only the
six columns of its two nodes, so the Jacobian has at most ten entries per edge and costs one
vectorised pass, whatever the graph's size (a finite-difference one over ``jac_sparsity``
needed as many residual evaluations as the graph has colours, dozens once loops close). A
Huber loss keeps a false loop closure from dragging the whole graph: beyond ``huber_scale``
standard deviations its pull stops growing.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import numpy.typing as npt
from scipy import sparse
from scipy.optimize import least_squares

log = logging.getLogger(__name__)


@dataclass(slots=True)
class PoseGraph:
    """Nodes and edges, kept in growable lists; :meth:`arrays` stacks them for the solver.

    Attributes:
        poses: node poses (x, y, theta); only appended to, and replaced by a new list when
            optimised (so a holder of the list knows the poses it saw have not moved).
        edges_i, edges_j: node indices of each edge.
        measurements: each edge's ``z`` (x, y, theta).
        sigmas: each edge's standard deviations (x [m], y [m], theta [rad]).
    """

    poses: list[tuple[float, float, float]] = field(default_factory=list)
    edges_i: list[int] = field(default_factory=list)
    edges_j: list[int] = field(default_factory=list)
    measurements: list[tuple[float, float, float]] = field(default_factory=list)
    sigmas: list[tuple[float, float, float]] = field(default_factory=list)
    robust: list[bool] = field(default_factory=list)

    def add_node(self, x: float, y: float, theta: float) -> int:
        self.poses.append((x, y, theta))
        return len(self.poses) - 1

    def add_edge(self, i: int, j: int, z: tuple[float, float, float],
                 sigma: tuple[float, float, float], *, robust: bool = False) -> None:
        """Add ``x_i⁻¹ ⊕ x_j ≈ z``; a ``robust`` edge (a loop closure) may be found an outlier."""
        self.robust.append(robust)
        self.edges_i.append(i)
        self.edges_j.append(j)
        self.measurements.append(z)
        self.sigmas.append(sigma)

    def optimize(self, *, huber_scale: float, outlier_sigmas: float = 6.0,
                 max_nfev: int = 50) -> int:
        """Optimise the node poses in place; returns how many robust edges were rejected."""
        if len(self.poses) < 2 or not self.edges_i:
            return 0
        poses, active = optimize(
            np.asarray(self.poses, dtype=np.float64),
            np.asarray(self.edges_i, dtype=np.int64),
            np.asarray(self.edges_j, dtype=np.int64),
            np.asarray(self.measurements, dtype=np.float64),
            np.asarray(self.sigmas, dtype=np.float64),
            np.asarray(self.robust, dtype=bool),
            huber_scale=huber_scale,
            outlier_sigmas=outlier_sigmas,
            max_nfev=max_nfev,
        )
        self.poses = [tuple(p) for p in poses.tolist()]
        dropped = np.flatnonzero(~active).tolist()
        # A rejected edge leaves the graph for good, so later solves do not weigh it again.
        for name in ("edges_i", "edges_j", "measurements", "sigmas", "robust"):
            values = getattr(self, name)
            setattr(self, name, [v for k, v in enumerate(values) if active[k]])
        return len(dropped)


def edge_residuals(
    poses: npt.NDArray[np.float64],
    i: npt.NDArray[np.int64],
    j: npt.NDArray[np.int64],
    z: npt.NDArray[np.float64],
) -> npt.NDArray[np.float64]:
    """(E, 3) errors ``z⁻¹ ⊕ (x_i⁻¹ ⊕ x_j)`` (heading wrapped into (-pi, pi])."""
    xi, xj = poses[i], poses[j]
    ci, si = np.cos(xi[:, 2]), np.sin(xi[:, 2])
    dx, dy = xj[:, 0] - xi[:, 0], xj[:, 1] - xi[:, 1]
    rx = ci * dx + si * dy
    ry = -si * dx + ci * dy
    rt = xj[:, 2] - xi[:, 2]
    cz, sz = np.cos(z[:, 2]), np.sin(z[:, 2])
    ex = rx - z[:, 0]
    ey = ry - z[:, 1]
    out = np.empty_like(z)
    out[:, 0] = cz * ex + sz * ey
    out[:, 1] = -sz * ex + cz * ey
    d = rt - z[:, 2]
    out[:, 2] = np.arctan2(np.sin(d), np.cos(d))
    return out


def optimize(
    poses: npt.NDArray[np.float64],
    i: npt.NDArray[np.int64],
    j: npt.NDArray[np.int64],
    z: npt.NDArray[np.float64],
    sigma: npt.NDArray[np.float64],
    robust: npt.NDArray[np.bool_],
    *,
    huber_scale: float,
    outlier_sigmas: float = 6.0,
    max_rejections: int = 5,
    max_nfev: int = 50,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """Least-squares node poses given the edges, node 0 fixed.

    A robust loss alone converges slowly from an estimate far from the answer, which is exactly
    where a loop closure leaves a drifted trajectory; so the graph is first solved with a plain
    quadratic loss, the worst robust edge (loop closure) more than ``outlier_sigmas`` standard
    deviations off is dropped and the solve repeated (at most ``max_rejections`` times), and the
    result is polished with the Huber loss, which then starts near its optimum.

    Args:
        poses: (N, 3) initial poses.
        i, j: (E,) node indices of the edges.
        z: (E, 3) measured ``x_i⁻¹ ⊕ x_j``.
        sigma: (E, 3) standard deviations of ``z`` [m, m, rad].
        robust: (E,) edges that may be rejected as outliers.
        huber_scale: Huber threshold in standard deviations.
        outlier_sigmas: a robust edge whose whitened error norm exceeds this is an outlier.
        max_rejections: at most this many edges are dropped.
        max_nfev: evaluation budget of each solve.

    Returns:
        The optimised (N, 3) poses, headings wrapped, and which edges were kept.
    """
    active = np.ones(i.shape[0], dtype=bool)
    current = poses
    rejected = 0
    for _ in range(max_rejections + 1):
        current = _solve(current, i[active], j[active], z[active], sigma[active], loss="linear",
                         huber_scale=huber_scale, max_nfev=max_nfev)
        err = np.linalg.norm(edge_residuals(current, i, j, z) / sigma, axis=1)
        err[~(robust & active)] = 0.0
        worst = int(np.argmax(err))
        if err[worst] <= outlier_sigmas:
            break
        active[worst] = False
        rejected += 1
    current = _solve(current, i[active], j[active], z[active], sigma[active], loss="huber",
                     huber_scale=huber_scale, max_nfev=max_nfev)
    if rejected:
        log.info("pose graph: %d loop closures rejected as outliers", rejected)
    return current, active


def _solve(
    poses: npt.NDArray[np.float64],
    i: npt.NDArray[np.int64],
    j: npt.NDArray[np.int64],
    z: npt.NDArray[np.float64],
    sigma: npt.NDArray[np.float64],
    *,
    loss: Literal["linear", "huber"],
    huber_scale: float,
    max_nfev: int,
) -> npt.NDArray[np.float64]:
    n = poses.shape[0]
    e = i.shape[0]
    weight = 1.0 / sigma
    fixed = poses[0].copy()

    def unpack(v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        return np.vstack([fixed[None, :], v.reshape(n - 1, 3)])

    def residuals(v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        return (edge_residuals(unpack(v), i, j, z) * weight).ravel()

    def jacobian(v: npt.NDArray[np.float64]) -> sparse.csr_matrix:
        return _jacobian(unpack(v), i, j, z, weight)

    start = poses[1:].ravel()
    result = least_squares(
        residuals, start, jac=jacobian, method="trf", tr_solver="lsmr",
        loss=loss, f_scale=huber_scale, x_scale="jac", max_nfev=max_nfev,
        xtol=1e-8, ftol=1e-8,
    )
    out = unpack(result.x)
    out[:, 2] = np.arctan2(np.sin(out[:, 2]), np.cos(out[:, 2]))
    log.debug("pose graph: %d nodes, %d edges, %s cost %.3g in %d evaluations", n, e, loss,
              result.cost, result.nfev)
    return out


def _jacobian(
    poses: npt.NDArray[np.float64],
    i: npt.NDArray[np.int64],
    j: npt.NDArray[np.int64],
    z: npt.NDArray[np.float64],
    weight: npt.NDArray[np.float64],
) -> sparse.csr_matrix:
    """The sparse Jacobian of the whitened residuals over the free nodes (all but node 0).

    With ``A`` the rotation by ``-(theta_i + theta_z)``, the translation error is
    ``A (t_j - t_i) - R(-theta_z) t_z``: its derivative is ``A`` in ``t_j``, ``-A`` in ``t_i``
    and ``dA/dtheta_i (t_j - t_i)`` in ``theta_i``; the heading error is
    ``theta_j - theta_i - theta_z``. Each edge fills 3 rows and at most 10 entries.
    """
    e = i.shape[0]
    xi, xj = poses[i], poses[j]
    a = xi[:, 2] + z[:, 2]
    c, s = np.cos(a), np.sin(a)
    dx, dy = xj[:, 0] - xi[:, 0], xj[:, 1] - xi[:, 1]
    # A = [[c, s], [-s, c]]; dA/dtheta = [[-s, c], [-c, -s]].
    w0, w1, w2 = weight[:, 0], weight[:, 1], weight[:, 2]
    r0, r1, r2 = 3 * np.arange(e), 3 * np.arange(e) + 1, 3 * np.arange(e) + 2
    ci, cj = 3 * (i - 1), 3 * (j - 1)
    rows = np.concatenate([r0, r0, r0, r1, r1, r1, r2, r0, r0, r1, r1, r2])
    cols = np.concatenate([ci, ci + 1, ci + 2, ci, ci + 1, ci + 2, ci + 2,
                           cj, cj + 1, cj, cj + 1, cj + 2])
    vals = np.concatenate([
        -c * w0, -s * w0, (-s * dx + c * dy) * w0,
        s * w1, -c * w1, (-c * dx - s * dy) * w1,
        -w2,
        c * w0, s * w0, -s * w1, c * w1, w2,
    ])
    keep = cols >= 0
    n = poses.shape[0]
    return sparse.csr_matrix((vals[keep], (rows[keep], cols[keep])), shape=(3 * e, 3 * (n - 1)))
