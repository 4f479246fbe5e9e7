"""Plane geometry of a footprint's outline, in Python: validation and containment of polygons."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from polynav.footprint.kernels import inside_or_on, seg_dist


def signed_area(pts: npt.NDArray[np.float64]) -> float:
    x, y = pts[:, 0], pts[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _orient(ax: float, ay: float, bx: float, by: float, cx: float, cy: float) -> float:
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


def _on_segment(ax: float, ay: float, bx: float, by: float, px: float, py: float) -> bool:
    return min(ax, bx) - 1e-12 <= px <= max(ax, bx) + 1e-12 and (
        min(ay, by) - 1e-12 <= py <= max(ay, by) + 1e-12
    )


def _segments_intersect(
    a: npt.NDArray[np.float64],
    b: npt.NDArray[np.float64],
    c: npt.NDArray[np.float64],
    d: npt.NDArray[np.float64],
) -> bool:
    d1 = _orient(*c, *d, *a)
    d2 = _orient(*c, *d, *b)
    d3 = _orient(*a, *b, *c)
    d4 = _orient(*a, *b, *d)
    if ((d1 > 0 > d2) or (d1 < 0 < d2)) and ((d3 > 0 > d4) or (d3 < 0 < d4)):
        return True
    tol = 1e-12
    return (
        (abs(d1) <= tol and _on_segment(*c, *d, *a))
        or (abs(d2) <= tol and _on_segment(*c, *d, *b))
        or (abs(d3) <= tol and _on_segment(*a, *b, *c))
        or (abs(d4) <= tol and _on_segment(*a, *b, *d))
    )


def segments_cross(
    a: npt.NDArray[np.float64],
    b: npt.NDArray[np.float64],
    c: npt.NDArray[np.float64],
    d: npt.NDArray[np.float64],
) -> bool:
    """Do the segments cross properly (each strictly splits the other; touching is not)?"""
    d1, d2 = _orient(*c, *d, *a), _orient(*c, *d, *b)
    d3, d4 = _orient(*a, *b, *c), _orient(*a, *b, *d)
    return ((d1 > 1e-12 and d2 < -1e-12) or (d1 < -1e-12 and d2 > 1e-12)) and (
        (d3 > 1e-12 and d4 < -1e-12) or (d3 < -1e-12 and d4 > 1e-12)
    )


def self_intersection(pts: npt.NDArray[np.float64]) -> tuple[int, int] | None:
    """The first pair of edges that touch other than at their shared vertex, or ``None``."""
    m = pts.shape[0]
    for i in range(m):
        a, b = pts[i], pts[(i + 1) % m]
        for j in range(i + 1, m):
            if j == i + 1 or (i == 0 and j == m - 1):
                # Neighbours share a vertex; they cross only if they fold back onto each other.
                c, d = pts[j], pts[(j + 1) % m]
                shared = b if j == i + 1 else a
                other_i = a if j == i + 1 else b
                other_j = d if j == i + 1 else c
                if abs(_orient(*other_i, *shared, *other_j)) <= 1e-12:
                    u = other_i - shared
                    v = other_j - shared
                    if float(np.dot(u, v)) > 0.0:
                        return (i, j)
                continue
            if _segments_intersect(a, b, pts[j], pts[(j + 1) % m]):
                return (i, j)
    return None


def point_segment_distance(
    px: float, py: float, ax: float, ay: float, bx: float, by: float
) -> float:
    return float(seg_dist(px, py, ax, ay, bx, by))


def contains(pts: npt.NDArray[np.float64], x: float, y: float) -> bool:
    return bool(inside_or_on(pts, x, y))


# --- kernels -------------------------------------------------------------------------------------
