from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.mapping import branch_and_bound as bnb


def _brute(table: np.ndarray, points: np.ndarray, x: float, y: float, thetas: np.ndarray,
           w: int) -> tuple[float, int, int, int]:
    h, wid = table.shape
    best = (-1.0, 0, 0, 0)
    for r, t in enumerate(thetas):
        bx = np.floor(x + math.cos(t) * points[:, 0] - math.sin(t) * points[:, 1]).astype(int)
        by = np.floor(y + math.sin(t) * points[:, 0] + math.cos(t) * points[:, 1]).astype(int)
        for dx in range(-w, w + 1):
            for dy in range(-w, w + 1):
                ix, iy = bx + dx, by + dy
                ok = (ix >= 0) & (ix < wid) & (iy >= 0) & (iy < h)
                score = table[iy[ok], ix[ok]].sum() / points.shape[0]
                if score > best[0]:
                    best = (score, r, dx, dy)
    return best


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_branch_and_bound_finds_the_exhaustive_optimum(seed: int) -> None:
    rng = np.random.default_rng(seed)
    # Multiples of 1/255: the grids store bytes, and these survive exactly.
    table = (np.round(rng.random((40, 50)) ** 4 * 255.0) / 255.0).astype(np.float32)
    points = rng.uniform(-8.0, 8.0, size=(30, 2))
    pre = bnb.precompute(table, 3)
    step, half = 0.05, 0.1
    found = bnb.search(pre, points, x=25.3, y=20.6, theta=0.2, window_cells=11,
                       window_theta=half, theta_step=step, min_score=0.0)
    thetas = 0.2 + step * np.arange(-2, 3)
    score, r, dx, dy = _brute(table, points, 25.3, 20.6, thetas, 11)
    assert found is not None
    assert found.score == pytest.approx(score, abs=1e-6)
    assert (found.x, found.y, found.theta) == pytest.approx((25.3 + dx, 20.6 + dy, thetas[r]))


def test_nothing_above_the_threshold_is_none() -> None:
    table = np.zeros((16, 16), dtype=np.float32)
    pre = bnb.precompute(table, 2)
    assert bnb.search(pre, np.array([[1.0, 0.0]]), x=8.0, y=8.0, theta=0.0, window_cells=4,
                      window_theta=0.1, theta_step=0.05, min_score=0.1) is None


def _brute_outside(table: np.ndarray, points: np.ndarray, x: float, y: float,
                   thetas: np.ndarray, w: int, ex: bnb.Exclusion,
                   mask: np.ndarray | None = None) -> float:
    best = -1.0
    for t in thetas:
        near = abs(math.remainder(t - ex.theta, 2.0 * math.pi)) <= ex.theta_radius
        bx = np.floor(x + math.cos(t) * points[:, 0] - math.sin(t) * points[:, 1]).astype(int)
        by = np.floor(y + math.sin(t) * points[:, 0] + math.cos(t) * points[:, 1]).astype(int)
        for dx in range(-w, w + 1):
            for dy in range(-w, w + 1):
                if near and math.hypot(x + dx - ex.x, y + dy - ex.y) <= ex.radius:
                    continue
                if mask is not None and not mask[math.floor(y + dy), math.floor(x + dx)]:
                    continue
                ix, iy = bx + dx, by + dy
                ok = (ix >= 0) & (ix < table.shape[1]) & (iy >= 0) & (iy < table.shape[0])
                best = max(best, float(table[iy[ok], ix[ok]].sum() / points.shape[0]))
    return best


@pytest.mark.parametrize("seed", [0, 1])
def test_an_excluded_neighbourhood_gives_the_exact_best_distinct_pose(seed: int) -> None:
    rng = np.random.default_rng(seed)
    table = (np.round(rng.random((40, 50)) ** 4 * 255.0) / 255.0).astype(np.float32)
    points = rng.uniform(-8.0, 8.0, size=(30, 2))
    pre = bnb.precompute(table, 3)
    thetas = np.array([-3.1, -1.0, 0.0, 0.1, 0.2, 3.1])
    best = bnb.search_headings(pre, points, x=25.3, y=20.6, thetas=thetas, window_cells=11,
                               min_score=0.0)
    assert best is not None
    ex = bnb.Exclusion(best.x, best.y, 4.5, best.theta, 0.15)
    other = bnb.search_headings(pre, points, x=25.3, y=20.6, thetas=thetas, window_cells=11,
                                min_score=0.0, exclude=ex)
    assert other is not None
    assert other.score == pytest.approx(
        _brute_outside(table, points, 25.3, 20.6, thetas, 11, ex), abs=1e-6)
    assert other.score <= best.score
    near = abs(math.remainder(other.theta - best.theta, 2.0 * math.pi)) <= 0.15
    assert not near or math.hypot(other.x - best.x, other.y - best.y) > 4.5


def test_poses_are_only_searched_where_the_mask_allows() -> None:
    rng = np.random.default_rng(3)
    table = (np.round(rng.random((40, 50)) ** 4 * 255.0) / 255.0).astype(np.float32)
    mask = rng.random((40, 50)) < 0.2
    points = rng.uniform(-8.0, 8.0, size=(30, 2))
    pre = bnb.precompute(table, 3)
    allowed = bnb.precompute(mask.astype(np.float32), 3)
    thetas = np.array([-1.0, 0.0, 0.1, 2.0])
    nowhere = bnb.Exclusion(0.0, 0.0, 0.0, 0.0, 0.0)
    found = bnb.search_headings(pre, points, x=25.3, y=20.6, thetas=thetas, window_cells=11,
                                min_score=0.0, allowed=allowed)
    assert found is not None
    assert mask[math.floor(found.y), math.floor(found.x)]
    assert found.score == pytest.approx(
        _brute_outside(table, points, 25.3, 20.6, thetas, 11, nowhere, mask), abs=1e-6)
