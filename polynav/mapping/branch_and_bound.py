"""Exact multi-resolution search of a scan over a grid by branch and bound.

After Olson ("Real-Time Correlative Scan Matching", ICRA 2009, §IV) and Hess et al.
("Real-Time Loop Closure in 2D LIDAR SLAM", ICRA 2016, §V): the score of a pose is the mean table
value under the scan's endpoints. Precomputed grids hold, at level ``h``, the maximum of the table
over the ``2^h x 2^h`` block of cells starting at each cell; so the score of the endpoints on the
level-``h`` grid bounds from above the score of every one of the ``4^h`` translations a level-``h``
node stands for. Searching depth-first, best bound first, and pruning every node whose bound is
no better than the best leaf found (initially the acceptance threshold) gives the same answer as
the exhaustive search at the finest level, usually for a tiny fraction of its cost.

The search is over whole-cell translations (``-w..w`` cells each way) and a list of headings;
the caller refines the winner below a cell. Cells are indexed ``[iy, ix]``.

An :class:`Exclusion` removes a neighbourhood of poses from the search (those within a radius
*and* within a heading range of a given pose): a node whose whole block lies inside it is pruned,
a leaf inside it is skipped. Searching again with the winner excluded gives the exact best
*distinct* alternative, which is what global relocalization needs to tell a unique match from an
ambiguous one (a featureless hall, two identical rooms, a corridor). An ``allowed`` mask (its
own max-pooled levels, from :func:`precompute`) restricts the poses to some cells, the free
space of a map: a block holding no allowed cell is pruned at whatever level it is met.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np
import numpy.typing as npt


@dataclass(frozen=True, slots=True, eq=False)
class PrecomputedGrids:
    """The table max-pooled over ``2^h`` blocks for ``h = 0..depth``.

    Attributes:
        grids: (depth + 1, H + 2 pad, W + 2 pad) uint8, the table times 255 rounded *up* (so a
            bound stays a bound); level ``h`` at ``[h, iy + pad, ix + pad]`` holds the max of the
            table over cells ``[iy, iy + 2^h) x [ix, ix + 2^h)``. A byte, not a float, because
            every finished submap keeps ``depth + 1`` of these.
        pad: ``2^depth``, the margin that lets a block start left of or below the table.
        depth: the coarsest level.
    """

    grids: npt.NDArray[np.uint8]
    pad: int
    depth: int


def precompute(table: npt.NDArray[np.float32], depth: int) -> PrecomputedGrids:
    """Build the max-pooled levels of ``table`` (values in [0, 1], ``[iy, ix]``)."""
    pad = 1 << depth
    h, w = table.shape
    grids = np.zeros((depth + 1, h + 2 * pad, w + 2 * pad), dtype=np.uint8)
    grids[0, pad:pad + h, pad:pad + w] = np.ceil(np.clip(table, 0.0, 1.0) * 255.0)
    for level in range(depth):
        s = 1 << level
        g = grids[level]
        # A 2s block at (y, x) is four s blocks: at (y, x), (y, x + s), (y + s, x), (y + s, x + s).
        out = g.copy()
        np.maximum(out[:, :-s], g[:, s:], out=out[:, :-s])
        tmp = out.copy()
        np.maximum(out[:-s, :], tmp[s:, :], out=out[:-s, :])
        grids[level + 1] = out
    return PrecomputedGrids(grids, pad, depth)


@numba.njit(cache=True, nogil=True)
def _bound(grid: npt.NDArray[np.uint8], pad: int, bx: npt.NDArray[np.int64],
           by: npt.NDArray[np.int64], dx: int, dy: int) -> float:
    height, width = grid.shape
    acc = 0.0
    for k in range(bx.shape[0]):
        ix = bx[k] + dx + pad
        iy = by[k] + dy + pad
        if 0 <= ix < width and 0 <= iy < height:
            acc += grid[iy, ix]
    return float(acc / (255.0 * bx.shape[0]))


@numba.njit(cache=True, nogil=True)
def _excluded(near: npt.NDArray[np.uint8], r: int, x: int, y: int, size: int, ex_x: float,
              ex_y: float, radius: float) -> bool:
    """Whether every translation of the node (``size`` cells from ``(x, y)``, heading ``r``) lies
    within ``radius`` of ``(ex_x, ex_y)`` at a heading marked ``near``."""
    if near[r] == 0:
        return False
    far_x = max(abs(x - ex_x), abs(x + size - 1 - ex_x))
    far_y = max(abs(y - ex_y), abs(y + size - 1 - ex_y))
    return far_x * far_x + far_y * far_y <= radius * radius


@numba.njit(cache=True, nogil=True)
def _search(grids: npt.NDArray[np.uint8], pad: int, depth: int,
            bxs: npt.NDArray[np.int64], bys: npt.NDArray[np.int64], window: int,
            min_score: float, near: npt.NDArray[np.uint8], ex_x: float, ex_y: float,
            radius: float, allowed: npt.NDArray[np.uint8], allowed_pad: int, ox: int,
            oy: int) -> tuple[float, int, int, int]:
    n_rot = bxs.shape[0]
    top = 1 << depth
    n_top = (2 * window) // top + 1
    count = n_rot * n_top * n_top
    cand_score = np.empty(count, dtype=np.float64)
    cand_r = np.empty(count, dtype=np.int64)
    cand_x = np.empty(count, dtype=np.int64)
    cand_y = np.empty(count, dtype=np.int64)
    k = 0
    for r in range(n_rot):
        for i in range(n_top):
            dx = -window + i * top
            for j in range(n_top):
                dy = -window + j * top
                cand_score[k] = _bound(grids[depth], pad, bxs[r], bys[r], dx, dy)
                cand_r[k] = r
                cand_x[k] = dx
                cand_y[k] = dy
                k += 1
    order = np.argsort(-cand_score)
    best = min_score
    best_r, best_x, best_y = -1, 0, 0
    # Depth-first stack: (level, rotation, dx, dy, bound).
    cap = 4 * depth + 8
    st_level = np.empty(cap, dtype=np.int64)
    st_r = np.empty(cap, dtype=np.int64)
    st_x = np.empty(cap, dtype=np.int64)
    st_y = np.empty(cap, dtype=np.int64)
    st_b = np.empty(cap, dtype=np.float64)
    child_b = np.empty(4, dtype=np.float64)
    child_x = np.empty(4, dtype=np.int64)
    child_y = np.empty(4, dtype=np.int64)
    for o in range(count):
        c = order[o]
        if cand_score[c] <= best:
            break
        sp = 0
        st_level[0] = depth
        st_r[0] = cand_r[c]
        st_x[0] = cand_x[c]
        st_y[0] = cand_y[c]
        st_b[0] = cand_score[c]
        sp = 1
        while sp > 0:
            sp -= 1
            level = st_level[sp]
            r = st_r[sp]
            x = st_x[sp]
            y = st_y[sp]
            if st_b[sp] <= best or _excluded(near, r, x, y, 1 << level, ex_x, ex_y, radius):
                continue
            if allowed.shape[0] > level:
                ay = oy + y + allowed_pad
                ax = ox + x + allowed_pad
                inside = 0 <= ay < allowed.shape[1] and 0 <= ax < allowed.shape[2]
                if not inside or allowed[level, ay, ax] == 0:
                    continue
            if level == 0:
                best = st_b[sp]
                best_r, best_x, best_y = r, x, y
                continue
            half = 1 << (level - 1)
            n = 0
            for a in range(2):
                cx = x + a * half
                if cx > window:
                    continue
                for b in range(2):
                    cy = y + b * half
                    if cy > window:
                        continue
                    child_b[n] = _bound(grids[level - 1], pad, bxs[r], bys[r], cx, cy)
                    child_x[n] = cx
                    child_y[n] = cy
                    n += 1
            # Push worst first so the best child is popped next.
            idx = np.argsort(child_b[:n])
            for m in range(n):
                q = idx[m]
                if child_b[q] > best:
                    st_level[sp] = level - 1
                    st_r[sp] = r
                    st_x[sp] = child_x[q]
                    st_y[sp] = child_y[q]
                    st_b[sp] = child_b[q]
                    sp += 1
    return best, best_r, best_x, best_y


@dataclass(frozen=True, slots=True)
class Exclusion:
    """Poses left out of a search: within ``radius`` of ``(x, y)`` *and* within ``theta_radius``
    of ``theta`` (so a pose far enough in either position or heading stays in).

    Attributes:
        x, y: centre in the table's frame [cells].
        radius: [cells].
        theta: heading [rad].
        theta_radius: [rad].
    """

    x: float
    y: float
    radius: float
    theta: float
    theta_radius: float


@dataclass(frozen=True, slots=True)
class SearchResult:
    """The best whole-cell pose found, in cells and radians of the table's frame.

    Attributes:
        score: mean table value of the endpoints there.
        x, y: position [cells], continuous (the guess's fraction kept).
        theta: heading [rad].
    """

    score: float
    x: float
    y: float
    theta: float


def search(
    pre: PrecomputedGrids,
    points: npt.NDArray[np.float64],
    *,
    x: float,
    y: float,
    theta: float,
    window_cells: int,
    window_theta: float,
    theta_step: float,
    min_score: float,
) -> SearchResult | None:
    """Best pose within the window around (x, y, theta) scoring above ``min_score``, if any.

    Args:
        pre: the table's precomputed grids.
        points: (N, 2) endpoints in the robot frame [cells].
        x, y: guess position in the table's frame [cells] (cell (i, j) spans [i, i+1)).
        theta: guess heading [rad].
        window_cells: translation half-width [cells].
        window_theta: heading half-width [rad].
        theta_step: heading step [rad].
        min_score: nothing at or below this is returned.

    Returns:
        The best pose, or None when nothing in the window beats ``min_score``.
    """
    n_theta = int(math.ceil(window_theta / theta_step - 1e-9))
    thetas = theta + theta_step * np.arange(-n_theta, n_theta + 1, dtype=np.float64)
    return search_headings(pre, points, x=x, y=y, thetas=thetas, window_cells=window_cells,
                           min_score=min_score)


def search_headings(
    pre: PrecomputedGrids,
    points: npt.NDArray[np.float64],
    *,
    x: float,
    y: float,
    thetas: npt.NDArray[np.float64],
    window_cells: int,
    min_score: float,
    exclude: Exclusion | None = None,
    allowed: PrecomputedGrids | None = None,
) -> SearchResult | None:
    """Best pose at any of ``thetas`` within ``window_cells`` of (x, y), outside ``exclude``.

    Args:
        pre: the table's precomputed grids.
        points: (N, 2) endpoints in the robot frame [cells].
        x, y: window centre in the table's frame [cells].
        thetas: the headings searched [rad].
        window_cells: translation half-width [cells].
        min_score: nothing at or below this is returned.
        exclude: poses left out (see :class:`Exclusion`), or None.
        allowed: where a pose may be: :func:`precompute` of a 0/1 mask of the table's cells
            with at least ``pre.depth`` levels (a pose is in the cell its position falls in);
            None allows every cell.

    Returns:
        The best pose, or None when nothing searched beats ``min_score``.
    """
    c = np.cos(thetas)[:, None]
    s = np.sin(thetas)[:, None]
    px = points[:, 0][None, :]
    py = points[:, 1][None, :]
    bxs = np.ascontiguousarray(np.floor(x + c * px - s * py).astype(np.int64))
    bys = np.ascontiguousarray(np.floor(y + s * px + c * py).astype(np.int64))
    if exclude is None:
        near = np.zeros(len(thetas), dtype=np.uint8)
        ex_x = ex_y = radius = 0.0
    else:
        turn = np.angle(np.exp(1j * (np.asarray(thetas) - exclude.theta)))
        near = (np.abs(turn) <= exclude.theta_radius).astype(np.uint8)
        ex_x, ex_y, radius = exclude.x - x, exclude.y - y, exclude.radius
    if allowed is None:
        mask, mask_pad = np.zeros((0, 1, 1), dtype=np.uint8), 0
    else:
        if allowed.depth < pre.depth:
            raise ValueError("the allowed mask needs as many levels as the table")
        mask, mask_pad = allowed.grids, allowed.pad
    score, r, dx, dy = _search(pre.grids, pre.pad, pre.depth, bxs, bys, int(window_cells),
                               float(min_score), near, float(ex_x), float(ex_y), float(radius),
                               mask, mask_pad, math.floor(x), math.floor(y))
    if r < 0:
        return None
    return SearchResult(float(score), x + dx, y + dy, float(thetas[r]))


def warm_up() -> None:
    """Compile the kernels on a tiny table."""
    table = np.zeros((8, 8), dtype=np.float32)
    table[4, 4] = 1.0
    pre = precompute(table, 2)
    search_headings(pre, np.array([[0.5, 0.5]]), x=3.0, y=3.0, thetas=np.array([0.0, 0.01]),
                    window_cells=2, min_score=0.1, exclude=Exclusion(3.0, 3.0, 1.0, 0.0, 0.1),
                    allowed=precompute(table, 2))
