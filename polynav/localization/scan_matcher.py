"""Correlative scan matching: find the pose where a scan's endpoints best fit the map.

After Olson, "Real-Time Correlative Scan Matching" (ICRA 2009). The search is exhaustive over a
window of poses around a guess, so, unlike a gradient method alone, it cannot be trapped by a
local optimum inside the window:

1. **Coarse level** (wide windows only): translations every ``coarse_cells`` cells and headings
   every ``coarse_theta_step``, scored on the max-pooled likelihood
   (:func:`~polynav.localization.likelihood_field.coarse_likelihood`), which never underrates the
   fine poses a coarse one stands for. The best ``candidates`` coarse poses go on.
2. **Fine level**: every cell and every ``theta_step`` around each candidate (or over the whole
   window when there is no coarse level), scored on the sharp likelihood.
3. **Refinement**: a few Gauss-Newton steps on the bilinearly interpolated signed distance field
   (as in Kohlbrecher et al., "A Flexible and Scalable SLAM System", SSRR 2011), which takes the
   grid answer below one cell.

A score is the mean likelihood of the endpoints (in [0, 1]); a weak Gaussian prior around the
guess breaks the ties that featureless corridors leave, so an unconstrained direction stays where
odometry put it instead of sliding to the window's edge.

The kernels work in the grid's own frame and in cell units: a translation by whole cells only
shifts indices, which is what makes the exhaustive search cheap. Everything else (poses in the
world frame, windows in metres) stays in :class:`ScanMatcher`.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numba
import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.localization.likelihood_field import LikelihoodField, coarse_likelihood

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class SearchWindow:
    """Where and how finely to search around a guess.

    Attributes:
        xy: half-width of the translation window [m], in x and in y.
        theta: half-width of the heading window [rad].
        theta_step: fine heading step [rad].
        coarse: whether to run the coarse level first (worth it for wide windows only).
        coarse_theta_step: heading step of the coarse level [rad].
        candidates: how many coarse poses the fine level searches around.
    """

    xy: float
    theta: float
    theta_step: float
    coarse: bool = False
    coarse_theta_step: float = math.radians(2.0)
    candidates: int = 8


@dataclass(frozen=True, slots=True)
class Match:
    """The best pose found, how well the scan fits there, and how many endpoints were used.

    Attributes:
        pose: robot pose on the map.
        score: mean endpoint likelihood at ``pose``, in [0, 1].
        inliers: fraction of endpoints within the inlier distance of a map surface, in [0, 1].
        points: endpoints used.
    """

    pose: Pose2D
    score: float
    inliers: float
    points: int


class ScanMatcher:
    """Matches scans against one map's likelihood field.

    Args:
        field: the map's likelihood field.
        coarse_cells: translation step of the coarse level [cells]; also the half-width of the
            max-pooling that builds the coarse table.
    """

    def __init__(self, field: LikelihoodField, *, coarse_cells: int = 2) -> None:
        self.field = field
        self.coarse_cells = max(1, int(coarse_cells))
        self._coarse = coarse_likelihood(field, self.coarse_cells)
        self._fine = field.likelihood
        self._distance = field.distance
        self._origin_inverse = field.info.origin.inverse()

    def match(
        self,
        points: npt.NDArray[np.float64],
        guess: Pose2D,
        window: SearchWindow,
        *,
        prior_xy: float = math.inf,
        prior_theta: float = math.inf,
        inlier_distance: float = 0.1,
        refine: bool = True,
    ) -> Match:
        """The pose within ``window`` of ``guess`` where ``points`` best fit the map.

        Args:
            points: (N, 2) endpoints in the robot frame [m] (sensor mount already applied).
            guess: where to centre the search (map frame).
            window: the search window.
            prior_xy: standard deviation [m] of the Gaussian prior around ``guess`` on
                translation; ``inf`` for none.
            prior_theta: the same on heading [rad].
            inlier_distance: an endpoint this close [m] to a map surface counts as an inlier.
            refine: whether to run the Gauss-Newton refinement.

        Returns:
            The best pose with its score; the guess itself, scored, when there are no points.
        """
        res = self.field.info.resolution
        pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
        px = np.ascontiguousarray(pts[:, 0] / res)
        py = np.ascontiguousarray(pts[:, 1] / res)
        local = self._origin_inverse.compose(guess)
        gx, gy, gt = local.x / res, local.y / res, local.theta
        if px.shape[0] == 0:
            return Match(guess, 0.0, 0.0, 0)
        half_cells = max(0, int(math.ceil(window.xy / res - 1e-9)))
        wx = (1.0 / (2.0 * (prior_xy / res) ** 2)) if math.isfinite(prior_xy) else 0.0
        wt = (1.0 / (2.0 * prior_theta**2)) if math.isfinite(prior_theta) else 0.0

        if window.coarse and half_cells > self.coarse_cells:
            seeds = self._coarse_seeds(px, py, gx, gy, gt, half_cells, window, wx, wt)
            c = self.coarse_cells
            fine_half = int(math.ceil(0.5 * window.coarse_theta_step / window.theta_step - 1e-9))
            best = (-1.0, 0.0, 0.0, 0.0)
            for ox, oy, theta in seeds:
                xs = np.arange(ox - c, ox + c + 1, dtype=np.int64)
                ys = np.arange(oy - c, oy + c + 1, dtype=np.int64)
                steps = np.arange(-fine_half, fine_half + 1, dtype=np.float64)
                thetas = theta + window.theta_step * steps
                cand = self._best(px, py, gx, gy, gt, xs, ys, thetas, wx, wt)
                if cand[0] > best[0]:
                    best = cand
        else:
            xs = np.arange(-half_cells, half_cells + 1, dtype=np.int64)
            n_theta = int(math.ceil(window.theta / window.theta_step - 1e-9))
            thetas = gt + window.theta_step * np.arange(-n_theta, n_theta + 1, dtype=np.float64)
            best = self._best(px, py, gx, gy, gt, xs, xs, thetas, wx, wt)
        _, bx, by, bt = best

        if refine:
            rx, ry, rt = _refine(self._distance, res, bx, by, bt, px, py, 3.0, 10)
            # Trust the refinement only near the grid answer: farther, it has slid along a
            # direction the scan does not constrain.
            if (abs(rx - bx) <= 1.5 and abs(ry - by) <= 1.5
                    and abs(rt - bt) <= max(window.theta_step, math.radians(1.0))):
                bx, by, bt = rx, ry, rt
        score, inliers = _evaluate(self._fine, self._distance, res, bx, by, bt, px, py,
                                   inlier_distance / res)
        pose = self.field.info.origin.compose(Pose2D(bx * res, by * res, bt))
        return Match(pose, float(score), float(inliers), int(px.shape[0]))

    def evaluate(
        self, points: npt.NDArray[np.float64], pose: Pose2D, *, inlier_distance: float = 0.1
    ) -> Match:
        """Score ``points`` at ``pose`` without searching."""
        res = self.field.info.resolution
        pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
        if pts.shape[0] == 0:
            return Match(pose, 0.0, 0.0, 0)
        local = self._origin_inverse.compose(pose)
        score, inliers = _evaluate(
            self._fine, self._distance, res, local.x / res, local.y / res, local.theta,
            np.ascontiguousarray(pts[:, 0] / res), np.ascontiguousarray(pts[:, 1] / res),
            inlier_distance / res,
        )
        return Match(pose, float(score), float(inliers), int(pts.shape[0]))

    def information(
        self, points: npt.NDArray[np.float64], pose: Pose2D, *, max_distance: float = 0.15
    ) -> npt.NDArray[np.float64]:
        """The Gauss-Newton normal matrix of ``points`` fitted at ``pose`` (map frame).

        ``H = sum J^T J`` over the endpoints within ``max_distance`` [m] of a map surface, where
        ``J`` is the derivative of an endpoint's signed surface distance [m] with respect to the
        pose (x [m], y [m], theta [rad]). Its x/y block counts endpoints' worth of surface
        facing each direction; :func:`polynav.localization.degeneracy.constraint` reads it.
        Endpoints farther from any surface (people, clutter) say nothing and are left out.

        Returns:
            ``H`` (3x3), symmetric, positive semi-definite; zeros when no endpoint is near a
            surface.
        """
        res = self.field.info.resolution
        pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
        h = np.zeros((3, 3), dtype=np.float64)
        if pts.shape[0] == 0:
            return h
        local = self._origin_inverse.compose(pose)
        _normal_matrix(self._distance, res, local.x / res, local.y / res, local.theta,
                       np.ascontiguousarray(pts[:, 0] / res),
                       np.ascontiguousarray(pts[:, 1] / res), max_distance / res, h)
        # The kernel works in the grid frame; turn the translation block into the map frame.
        c, s = math.cos(self.field.info.origin.theta), math.sin(self.field.info.origin.theta)
        t = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
        world: npt.NDArray[np.float64] = t.T @ h @ t
        return world

    def _coarse_seeds(
        self,
        px: npt.NDArray[np.float64],
        py: npt.NDArray[np.float64],
        gx: float,
        gy: float,
        gt: float,
        half_cells: int,
        window: SearchWindow,
        wx: float,
        wt: float,
    ) -> list[tuple[int, int, float]]:
        c = self.coarse_cells
        n = int(math.ceil(half_cells / c))
        xs = c * np.arange(-n, n + 1, dtype=np.int64)
        n_theta = int(math.ceil(window.theta / window.coarse_theta_step - 1e-9))
        thetas = gt + window.coarse_theta_step * np.arange(-n_theta, n_theta + 1, dtype=np.float64)
        volume = np.empty((thetas.shape[0], xs.shape[0], xs.shape[0]), dtype=np.float64)
        _score_volume(self._coarse, gx, gy, px, py, thetas, xs, xs, volume)
        _apply_prior(volume, xs, xs, thetas - gt, wx, wt)
        k = min(max(1, window.candidates), volume.size)
        flat = volume.ravel()
        top = np.argpartition(-flat, k - 1)[:k]
        top = top[np.argsort(-flat[top])]
        seeds = []
        for index in top:
            t, i, j = np.unravel_index(index, volume.shape)
            seeds.append((int(xs[i]), int(xs[j]), float(thetas[t])))
        return seeds

    def _best(
        self,
        px: npt.NDArray[np.float64],
        py: npt.NDArray[np.float64],
        gx: float,
        gy: float,
        gt: float,
        xs: npt.NDArray[np.int64],
        ys: npt.NDArray[np.int64],
        thetas: npt.NDArray[np.float64],
        wx: float,
        wt: float,
    ) -> tuple[float, float, float, float]:
        """Best (score, x, y, theta) of a fine volume, pose in grid cells."""
        volume = np.empty((thetas.shape[0], xs.shape[0], ys.shape[0]), dtype=np.float64)
        _score_volume(self._fine, gx, gy, px, py, thetas, xs, ys, volume)
        score, t, i, j = _best_with_prior(volume, xs, ys, thetas, gt, wx, wt)
        # The kernel scores the rotated points offset by whole cells from the guess.
        return (score, gx + float(xs[i]), gy + float(ys[j]), float(thetas[t]))


def _apply_prior(
    volume: npt.NDArray[np.float64],
    xs: npt.NDArray[np.int64],
    ys: npt.NDArray[np.int64],
    dthetas: npt.NDArray[np.float64],
    wx: float,
    wt: float,
) -> None:
    if wx == 0.0 and wt == 0.0:
        return
    d2 = xs[:, None].astype(np.float64) ** 2 + ys[None, :].astype(np.float64) ** 2
    penalty = np.exp(-wx * d2[None, :, :] - wt * (dthetas**2)[:, None, None])
    volume *= penalty


@numba.njit(cache=True, nogil=True)
def _best_with_prior(
    volume: npt.NDArray[np.float64],
    xs: npt.NDArray[np.int64],
    ys: npt.NDArray[np.int64],
    thetas: npt.NDArray[np.float64],
    gt: float,
    wx: float,
    wt: float,
) -> tuple[float, int, int, int]:
    """The best ``(score, t, i, j)`` of ``volume`` weighted by :func:`_apply_prior`'s prior
    (the first of equal ones, as ``np.argmax``): one pass, where the array operations cost
    more than the arithmetic on a fine volume of a few hundred poses."""
    weighted = wx != 0.0 or wt != 0.0
    best = -np.inf
    bt = bi = bj = 0
    for t in range(volume.shape[0]):
        dt = thetas[t] - gt
        for i in range(volume.shape[1]):
            for j in range(volume.shape[2]):
                v = volume[t, i, j]
                if weighted:
                    d2 = float(xs[i]) ** 2 + float(ys[j]) ** 2
                    v *= math.exp(-wx * d2 - wt * dt**2)
                if v > best:
                    best, bt, bi, bj = v, t, i, j
    return best, bt, bi, bj


@numba.njit(cache=True, nogil=True)
def _score_volume(
    table: npt.NDArray[np.float32],
    gx: float,
    gy: float,
    px: npt.NDArray[np.float64],
    py: npt.NDArray[np.float64],
    thetas: npt.NDArray[np.float64],
    xs: npt.NDArray[np.int64],
    ys: npt.NDArray[np.int64],
    out: npt.NDArray[np.float64],
) -> None:
    """Mean table value of the points rotated by each theta about (gx, gy) and shifted by whole
    cells (xs[i], ys[j]): ``out[t, i, j]``. Points and (gx, gy) in cells, grid frame.

    Point by point, each point's whole window of shifts is read at once: a few neighbouring
    rows of the table instead of one cell per point per shift, which on a floor-sized table
    missed the cache at every read (a third faster). Each sum still adds the points in order,
    so the scores are the same to the bit.
    """
    height, width = table.shape
    n = px.shape[0]
    nx = xs.shape[0]
    ny = ys.shape[0]
    acc = np.empty((ny, nx), dtype=np.float64)
    inv = 1.0 / n
    for t in range(thetas.shape[0]):
        c = math.cos(thetas[t])
        s = math.sin(thetas[t])
        acc[:, :] = 0.0
        for k in range(n):
            bx = int(math.floor(gx + c * px[k] - s * py[k]))
            by = int(math.floor(gy + s * px[k] + c * py[k]))
            for j in range(ny):
                iy = by + ys[j]
                if iy < 0 or iy >= height:
                    continue
                for i in range(nx):
                    ix = bx + xs[i]
                    if 0 <= ix < width:
                        acc[j, i] += table[iy, ix]
        for i in range(nx):
            for j in range(ny):
                out[t, i, j] = acc[j, i] * inv


@numba.njit(cache=True, nogil=True)
def _sample(
    field: npt.NDArray[np.float32], u: float, v: float
) -> tuple[float, float, float, bool]:
    """Bilinear value and gradient (per cell) of ``field`` at continuous cell coords (u, v),
    cell centres at i + 0.5; ``ok`` is False off the grid."""
    height, width = field.shape
    x = u - 0.5
    y = v - 0.5
    ix = int(math.floor(x))
    iy = int(math.floor(y))
    if ix < 0 or iy < 0 or ix + 1 >= width or iy + 1 >= height:
        return 0.0, 0.0, 0.0, False
    fx = x - ix
    fy = y - iy
    v00 = field[iy, ix]
    v10 = field[iy, ix + 1]
    v01 = field[iy + 1, ix]
    v11 = field[iy + 1, ix + 1]
    value = ((1.0 - fx) * (1.0 - fy) * v00 + fx * (1.0 - fy) * v10
             + (1.0 - fx) * fy * v01 + fx * fy * v11)
    du = (1.0 - fy) * (v10 - v00) + fy * (v11 - v01)
    dv = (1.0 - fx) * (v01 - v00) + fx * (v11 - v10)
    return value, du, dv, True


@numba.njit(cache=True, nogil=True)
def _refine(
    distance: npt.NDArray[np.float32],
    res: float,
    x: float,
    y: float,
    theta: float,
    px: npt.NDArray[np.float64],
    py: npt.NDArray[np.float64],
    outlier_cells: float,
    iterations: int,
) -> tuple[float, float, float]:
    """Gauss-Newton on the sum of squared signed surface distances of the endpoints.

    Pose and points in cells, grid frame. Endpoints farther than ``outlier_cells`` from any
    surface are left out (people, moved furniture). A small damping keeps directions the scan
    does not constrain (along a corridor) where they are.
    """
    inv_res = 1.0 / res
    n = px.shape[0]
    for _ in range(iterations):
        c = math.cos(theta)
        s = math.sin(theta)
        h00 = h01 = h02 = h11 = h12 = h22 = 0.0
        g0 = g1 = g2 = 0.0
        used = 0
        for k in range(n):
            qx = x + c * px[k] - s * py[k]
            qy = y + s * px[k] + c * py[k]
            d, du, dv, ok = _sample(distance, qx, qy)
            if not ok:
                continue
            r = d * inv_res
            if abs(r) > outlier_cells:
                continue
            du *= inv_res
            dv *= inv_res
            jt = du * (-s * px[k] - c * py[k]) + dv * (c * px[k] - s * py[k])
            h00 += du * du
            h01 += du * dv
            h02 += du * jt
            h11 += dv * dv
            h12 += dv * jt
            h22 += jt * jt
            g0 += du * r
            g1 += dv * r
            g2 += jt * r
            used += 1
        if used < 3:
            break
        damping = 1e-3 * used
        h00 += damping
        h11 += damping
        h22 += damping * 100.0
        # Solve H d = -g by Cramer's rule (H symmetric 3x3, positive definite with damping).
        det = (h00 * (h11 * h22 - h12 * h12) - h01 * (h01 * h22 - h12 * h02)
               + h02 * (h01 * h12 - h11 * h02))
        if det <= 1e-12:
            break
        b0, b1, b2 = -g0, -g1, -g2
        d0 = (b0 * (h11 * h22 - h12 * h12) - h01 * (b1 * h22 - h12 * b2)
              + h02 * (b1 * h12 - h11 * b2)) / det
        d1 = (h00 * (b1 * h22 - b2 * h12) - b0 * (h01 * h22 - h12 * h02)
              + h02 * (h01 * b2 - b1 * h02)) / det
        d2 = (h00 * (h11 * b2 - h12 * b1) - h01 * (h01 * b2 - b1 * h02)
              + b0 * (h01 * h12 - h11 * h02)) / det
        # No single step farther than one cell or about one degree: the linearisation holds
        # only that far.
        scale = max(abs(d0), abs(d1), abs(d2) / 0.02, 1.0)
        x += d0 / scale
        y += d1 / scale
        theta += d2 / scale
        if abs(d0) < 1e-3 and abs(d1) < 1e-3 and abs(d2) < 1e-5:
            break
    return x, y, theta


@numba.njit(cache=True, nogil=True)
def _normal_matrix(
    distance: npt.NDArray[np.float32],
    res: float,
    x: float,
    y: float,
    theta: float,
    px: npt.NDArray[np.float64],
    py: npt.NDArray[np.float64],
    max_cells: float,
    out: npt.NDArray[np.float64],
) -> None:
    """``out += sum J^T J`` at a pose (grid frame, cells) over endpoints within ``max_cells``
    of a surface; ``J`` per metre of translation and per radian, in metres of distance."""
    c = math.cos(theta)
    s = math.sin(theta)
    inv_res = 1.0 / res
    for k in range(px.shape[0]):
        qx = x + c * px[k] - s * py[k]
        qy = y + s * px[k] + c * py[k]
        d, du, dv, ok = _sample(distance, qx, qy)
        if not ok or abs(d) * inv_res > max_cells:
            continue
        gu = du * inv_res
        gv = dv * inv_res
        jt = (gu * (-s * px[k] - c * py[k]) + gv * (c * px[k] - s * py[k])) * res
        j = (gu, gv, jt)
        for a in range(3):
            for b in range(3):
                out[a, b] += j[a] * j[b]


@numba.njit(cache=True, nogil=True)
def _evaluate(
    likelihood: npt.NDArray[np.float32],
    distance: npt.NDArray[np.float32],
    res: float,
    x: float,
    y: float,
    theta: float,
    px: npt.NDArray[np.float64],
    py: npt.NDArray[np.float64],
    inlier_cells: float,
) -> tuple[float, float]:
    """(mean likelihood, inlier fraction) of the endpoints at a pose in cells, grid frame."""
    height, width = likelihood.shape
    c = math.cos(theta)
    s = math.sin(theta)
    n = px.shape[0]
    acc = 0.0
    inliers = 0
    for k in range(n):
        qx = x + c * px[k] - s * py[k]
        qy = y + s * px[k] + c * py[k]
        ix = int(math.floor(qx))
        iy = int(math.floor(qy))
        if 0 <= ix < width and 0 <= iy < height:
            acc += likelihood[iy, ix]
        d, _, _, ok = _sample(distance, qx, qy)
        if ok and abs(d) / res <= inlier_cells:
            inliers += 1
    return acc / n, inliers / n


def scan_points(
    ranges: npt.NDArray[np.floating],
    angles: npt.NDArray[np.float64],
    *,
    range_min: float,
    range_max: float,
    sensor_pose: Pose2D,
    step: int = 1,
) -> npt.NDArray[np.float64]:
    """Endpoints (N, 2) [m] in the robot frame of every ``step``-th valid beam.

    Args:
        ranges: measured distances [m]; ``inf``/``nan`` or out of ``[range_min, range_max]``
            means no return and the beam is skipped.
        angles: beam angles [rad] in the sensor frame.
        range_min: shortest valid return [m].
        range_max: longest valid return [m]; a return at exactly ``range_max`` is kept.
        sensor_pose: the sensor's mount in the robot frame.
        step: keep every ``step``-th beam (counted over all beams, so the kept beams spread
            evenly whatever is missing).
    """
    r = np.asarray(ranges, dtype=np.float64)[::step]
    a = np.asarray(angles, dtype=np.float64)[::step]
    ok = np.isfinite(r) & (r >= range_min) & (r <= range_max)
    r = r[ok]
    a = a[ok] + sensor_pose.theta
    out = np.empty((r.shape[0], 2), dtype=np.float64)
    out[:, 0] = sensor_pose.x + r * np.cos(a)
    out[:, 1] = sensor_pose.y + r * np.sin(a)
    return out


def warm_up() -> None:
    """Compile the kernels on tiny inputs, so the first real scan is not slow."""
    table = np.zeros((4, 4), dtype=np.float32)
    px = np.array([0.5, 1.0])
    py = np.array([0.5, -0.5])
    out = np.empty((1, 1, 1), dtype=np.float64)
    offsets = np.zeros(1, dtype=np.int64)
    _score_volume(table, 1.5, 1.5, px, py, np.zeros(1), offsets, offsets, out)
    _best_with_prior(out, offsets, offsets, np.zeros(1), 0.0, 1.0, 1.0)
    _refine(table, 0.05, 1.5, 1.5, 0.0, px, py, 3.0, 1)
    _evaluate(table, table, 0.05, 1.5, 1.5, 0.0, px, py, 2.0)
    _normal_matrix(table, 0.05, 1.5, 1.5, 0.0, px, py, 3.0, np.zeros((3, 3)))
