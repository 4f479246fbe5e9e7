"""numba kernels of :class:`~polynav.control.tracked_path.TrackedPath`, run every control period.

The controller asks the tracked path where the robot is, where the carrot is and what lies along
the next metres, twenty times a second. Written with numpy each answer is a dozen small array
operations over a few hundred points, and their call overhead (not the arithmetic) was the cost:
on a 20-goal ``bench nav`` run the projection alone took 5 % of the CPU. These kernels do the
same arithmetic in one pass, in the same order, so they return what the numpy code returned.

Every kernel takes the path as its ``points`` (N, 2) and ``cumulative`` (N,) arrays, N >= 2.
"""

from __future__ import annotations

import functools
import math

import numba
import numpy as np
import numpy.typing as npt

from polynav.control import collision


@numba.njit(cache=True, nogil=True)
def segments(cumulative: npt.NDArray[np.float64], start: float, stop: float) -> tuple[int, int]:
    """Indices ``i0..i1`` of the segments (point i to i+1) overlapping [start, stop]; at least
    one, the first or the last, when the span lies before or beyond the path."""
    last = cumulative.shape[0] - 2
    i0 = min(max(int(np.searchsorted(cumulative, start, side="right")) - 1, 0), last)
    i1 = int(np.searchsorted(cumulative, stop, side="left"))
    return (i0, min(max(i1, i0 + 1), last + 1))


@numba.njit(cache=True, nogil=True)
def project(
    points: npt.NDArray[np.float64],
    cumulative: npt.NDArray[np.float64],
    x: float,
    y: float,
    start: float,
    window: float,
    use_heading: bool,
    heading: float,
    tie: float,
) -> float:
    """Arc length of the path point nearest (x, y) within [start, start + window]; among
    stretches within ``tie`` of the nearest, the one most along ``heading`` when
    ``use_heading`` (see ``TrackedPath.project``)."""
    i0, i1 = segments(cumulative, start, start + window)
    count = i1 - i0
    ts = np.empty(count)
    gaps = np.empty(count)
    best = 0
    for j in range(count):
        i = i0 + j
        ax, ay = points[i, 0], points[i, 1]
        dx, dy = points[i + 1, 0] - ax, points[i + 1, 1] - ay
        s_a = cumulative[i]
        seg = cumulative[i + 1] - s_a
        t = ((x - ax) * dx + (y - ay) * dy) / (seg * seg)
        # Keep the answer inside the window at both ends.
        t_lo = min(max((start - s_a) / seg, 0.0), 1.0)
        t_hi = min(max((start + window - s_a) / seg, 0.0), 1.0)
        t = min(max(t, t_lo), t_hi)
        gap = math.hypot(ax + t * dx - x, ay + t * dy - y)
        ts[j] = t
        gaps[j] = gap
        if gap < gaps[best]:
            best = j
    if use_heading:
        limit = gaps[best] + tie
        c, s = math.cos(heading), math.sin(heading)
        near = 0
        chosen = best
        top = -np.inf
        for j in range(count):
            if gaps[j] <= limit:
                near += 1
                i = i0 + j
                dx, dy = points[i + 1, 0] - points[i, 0], points[i + 1, 1] - points[i, 1]
                along = (dx * c + dy * s) / (cumulative[i + 1] - cumulative[i])
                if along > top:
                    top, chosen = along, j
        if near > 1:
            best = chosen
    i = i0 + best
    return float(cumulative[i] + ts[best] * (cumulative[i + 1] - cumulative[i]))


@numba.njit(cache=True, nogil=True)
def sample(
    points: npt.NDArray[np.float64],
    cumulative: npt.NDArray[np.float64],
    s: npt.NDArray[np.float64],
) -> npt.NDArray[np.float64]:
    """Poses (M, 3) at arc lengths ``s`` (M,): the point, clamped to the path and interpolated
    as ``np.interp`` does, and the heading of the segment holding it (``headings_at``)."""
    n = points.shape[0]
    out = np.empty((s.shape[0], 3))
    for k in range(s.shape[0]):
        v = s[k]
        seg = int(np.searchsorted(cumulative, v, side="right")) - 1
        seg = min(max(seg, 0), n - 2)
        dx = points[seg + 1, 0] - points[seg, 0]
        dy = points[seg + 1, 1] - points[seg, 1]
        out[k, 2] = math.atan2(dy, dx)
        if v <= cumulative[0]:
            out[k, 0], out[k, 1] = points[0, 0], points[0, 1]
        elif v >= cumulative[n - 1]:
            out[k, 0], out[k, 1] = points[n - 1, 0], points[n - 1, 1]
        else:
            # np.interp's arithmetic: slope times the offset, plus the left value.
            length = cumulative[seg + 1] - cumulative[seg]
            offset = v - cumulative[seg]
            out[k, 0] = dx / length * offset + points[seg, 0]
            out[k, 1] = dy / length * offset + points[seg, 1]
    return out


@numba.njit(cache=True, nogil=True)
def lookahead(
    points: npt.NDArray[np.float64],
    cumulative: npt.NDArray[np.float64],
    x: float,
    y: float,
    start: float,
    radius: float,
    window: float,
) -> tuple[bool, float, float]:
    """``TrackedPath.lookahead`` as ``(found, x, y)``; ``found`` False stands for its None."""
    n = points.shape[0]
    r2 = radius * radius
    at = sample(points, cumulative, np.array([start]))
    ax, ay = at[0, 0], at[0, 1]
    if (ax - x) ** 2 + (ay - y) ** 2 >= r2:
        return (True, ax, ay)
    j0 = int(np.searchsorted(cumulative, start, side="right"))
    j1 = int(np.searchsorted(cumulative, start + window, side="right")) + 1
    end = min(j1, n)
    if j0 >= end:
        return (False, 0.0, 0.0)
    k = -1
    for j in range(j0, end):
        if (points[j, 0] - x) ** 2 + (points[j, 1] - y) ** 2 >= r2:
            k = j
            break
    if k < 0:
        if j1 >= n:
            return (False, 0.0, 0.0)
        return (True, points[end - 1, 0], points[end - 1, 1])
    if k > j0:
        ax, ay = points[k - 1, 0], points[k - 1, 1]
    bx, by = points[k, 0], points[k, 1]
    # Where segment a->b (a inside the circle, b outside) leaves it.
    rax, ray = ax - x, ay - y
    dx, dy = (bx - x) - rax, (by - y) - ray
    qa = dx * dx + dy * dy
    qb = 2.0 * (rax * dx + ray * dy)
    qc = rax * rax + ray * ray - radius * radius
    disc = max(qb * qb - 4.0 * qa * qc, 0.0)
    t = min(max((-qb + math.sqrt(disc)) / (2.0 * qa), 0.0), 1.0)
    return (True, x + rax + t * dx, y + ray + t * dy)


@functools.cache
def warm_up() -> None:
    """Compile (or load from numba's cache) these kernels on a two-segment path, and the
    collision module's arc kernel, once per process:
    a controller calls it when built, so the first control period is not late by a compile."""
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    cumulative = np.array([0.0, 1.0, 2.0])
    project(points, cumulative, 0.5, 0.1, 0.0, 2.0, True, 0.0, 0.05)
    sample(points, cumulative, np.array([0.0, 0.5, 1.5, 3.0]))
    lookahead(points, cumulative, 0.5, 0.1, 0.5, 0.8, 2.0)
    collision.warm_up()
