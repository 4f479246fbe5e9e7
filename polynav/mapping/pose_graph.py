"""A 2-D pose graph and its sparse, robust least-squares optimisation.

Nodes are robot poses (x, y, theta) in the map frame; an edge ``(i, j, z)`` says that node ``j``
seen from node ``i`` is at ``z`` (``x_i⁻¹ ⊕ x_j ≈ z``), with a standard deviation per
component. The residual of an edge is ``z⁻¹ ⊕ (x_i⁻¹ ⊕ x_j)`` divided by those deviations
(Grisetti et al., "A Tutorial on Graph-Based SLAM", 2010, §IV, in the SE(2) form). Node 0 is
held fixed, which removes the gauge freedom.

:func:`optimize` hands the stacked residuals to ``scipy.optimize.least_squares`` (trust region
reflective with LSMR) with the Jacobian's sparsity pattern (``jac_sparsity``): each edge's three
rows touch only the six columns of its two nodes, so the finite-difference Jacobian costs a few
dozen residual evaluations, whatever the graph's size. A Huber loss keeps a false loop closure
from dragging the whole graph: beyond ``huber_scale`` standard deviations its pull stops growing.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt
from scipy import sparse
from scipy.optimize import least_squares

log = logging.getLogger(__name__)


@dataclass(slots=True)
class PoseGraph:
    """Nodes and edges, kept in growable lists; :meth:`arrays` stacks them for the solver.

    Attributes:
        poses: node poses (x, y, theta).
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
        poses, rejected = optimize(
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
        self.poses = [tuple(p) for p in poses.tolist()]  # type: ignore[misc]
        return rejected


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
) -> tuple[npt.NDArray[np.float64], int]:
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
        The optimised (N, 3) poses, headings wrapped, and how many edges were dropped.
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
        current = poses
    current = _solve(current, i[active], j[active], z[active], sigma[active], loss="huber",
                     huber_scale=huber_scale, max_nfev=max_nfev)
    if rejected:
        log.info("pose graph: %d loop closures rejected as outliers", rejected)
    return current, rejected


def _solve(
    poses: npt.NDArray[np.float64],
    i: npt.NDArray[np.int64],
    j: npt.NDArray[np.int64],
    z: npt.NDArray[np.float64],
    sigma: npt.NDArray[np.float64],
    *,
    loss: str,
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

    # Rows 3e..3e+2 depend on the columns of nodes i and j (node 0 has none: it is fixed).
    rows = np.repeat(np.arange(3 * e), 6)
    node_cols = np.stack([i, j], axis=1)  # (E, 2)
    cols = (3 * (node_cols[:, :, None] - 1) + np.arange(3)[None, None, :]).reshape(e, 6)
    cols = np.repeat(cols[:, None, :], 3, axis=1).reshape(-1)
    keep = cols >= 0
    pattern = sparse.coo_matrix(
        (np.ones(int(keep.sum()), dtype=np.int8), (rows[keep], cols[keep])),
        shape=(3 * e, 3 * (n - 1)),
    ).tocsr()
    start = poses[1:].ravel()
    result = least_squares(
        residuals, start, jac_sparsity=pattern, method="trf", tr_solver="lsmr",
        loss=loss, f_scale=huber_scale, x_scale="jac", max_nfev=max_nfev,
        xtol=1e-8, ftol=1e-8,
    )
    out = unpack(result.x)
    out[:, 2] = np.arctan2(np.sin(out[:, 2]), np.cos(out[:, 2]))
    log.debug("pose graph: %d nodes, %d edges, %s cost %.3g in %d evaluations", n, e, loss,
              result.cost, result.nfev)
    return out
