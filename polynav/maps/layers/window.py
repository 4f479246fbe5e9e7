"""Window arithmetic for the layered costmap: union, growth, clipping, and the window of a mask.

A window is ``(ix0, iy0, ix1, iy1)``, half-open (:data:`polynav.maps.interface.Window`); ``None``
means "nothing changed".
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from polynav.maps.interface import Window


def union(a: Window | None, b: Window | None) -> Window | None:
    """The smallest window holding both (``None`` is the empty window)."""
    if a is None:
        return b
    if b is None:
        return a
    return (min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3]))


def clip(window: Window | None, width: int, height: int) -> Window | None:
    """``window`` cut to a ``width`` x ``height`` grid; ``None`` if nothing is left."""
    if window is None:
        return None
    ix0, iy0 = max(window[0], 0), max(window[1], 0)
    ix1, iy1 = min(window[2], width), min(window[3], height)
    if ix0 >= ix1 or iy0 >= iy1:
        return None
    return (ix0, iy0, ix1, iy1)


def grow(window: Window, cells: int, width: int, height: int) -> Window:
    """``window`` grown by ``cells`` on every side, clipped to the grid."""
    grown = clip(
        (window[0] - cells, window[1] - cells, window[2] + cells, window[3] + cells), width, height
    )
    assert grown is not None  # a non-empty window inside the grid stays non-empty
    return grown


def slices(window: Window) -> tuple[slice, slice]:
    """Index ``grid[slices(window)]`` for the window's cells of a ``[iy, ix]`` array."""
    return (slice(window[1], window[3]), slice(window[0], window[2]))


def of_mask(mask: npt.NDArray[np.bool_]) -> Window | None:
    """The smallest window holding every ``True`` cell of ``mask`` (``None`` if there is none)."""
    rows = np.flatnonzero(mask.any(axis=1))
    if rows.size == 0:
        return None
    cols = np.flatnonzero(mask.any(axis=0))
    return (int(cols[0]), int(rows[0]), int(cols[-1]) + 1, int(rows[-1]) + 1)


def groups_of_mask(mask: npt.NDArray[np.bool_], gap: int) -> list[Window]:
    """Windows that together hold every ``True`` cell of ``mask``, one per group of cells.

    Cells closer than about ``gap`` cells share a group (the mask is cut into tiles of ``gap``
    cells, and touching tiles with a cell join); groups farther apart get windows of their
    own. A walker on one side of the robot and a door closing on the other are then two small
    windows instead of one that spans the scan.
    """
    boxes = _groups(np.ascontiguousarray(mask, dtype=np.bool_), max(int(gap), 1))
    return [(int(b[0]), int(b[1]), int(b[2]), int(b[3])) for b in boxes]


@numba.njit(cache=True, nogil=True)
def _groups(mask: npt.NDArray[np.bool_], t: int) -> npt.NDArray[np.int64]:
    h, w = mask.shape
    rows, cols = (h + t - 1) // t, (w + t - 1) // t
    # Per tile, the bounding box of its True cells (x0 = w means "no cell").
    box = np.empty((rows, cols, 4), dtype=np.int64)
    box[:, :, 0] = w
    box[:, :, 1] = h
    box[:, :, 2] = 0
    box[:, :, 3] = 0
    for y in range(h):
        ty = y // t
        for x in range(w):
            if mask[y, x]:
                b = box[ty, x // t]
                b[0] = min(b[0], x)
                b[1] = min(b[1], y)
                b[2] = max(b[2], x + 1)
                b[3] = max(b[3], y + 1)
    # Flood-fill the occupied tiles (8-connected) into groups, merging their boxes.
    label = np.full((rows, cols), -1, dtype=np.int64)
    out = np.empty((rows * cols, 4), dtype=np.int64)
    stack = np.empty((rows * cols, 2), dtype=np.int64)
    n = 0
    for r0 in range(rows):
        for c0 in range(cols):
            if label[r0, c0] >= 0 or box[r0, c0, 0] == w:
                continue
            label[r0, c0] = n
            g = out[n]
            g[0], g[1], g[2], g[3] = w, h, 0, 0
            stack[0, 0], stack[0, 1] = r0, c0
            top = 1
            while top > 0:
                top -= 1
                r, c = stack[top, 0], stack[top, 1]
                b = box[r, c]
                g[0] = min(g[0], b[0])
                g[1] = min(g[1], b[1])
                g[2] = max(g[2], b[2])
                g[3] = max(g[3], b[3])
                for dr in range(-1, 2):
                    for dc in range(-1, 2):
                        rr, cc = r + dr, c + dc
                        if (0 <= rr < rows and 0 <= cc < cols and label[rr, cc] < 0
                                and box[rr, cc, 0] != w):
                            label[rr, cc] = n
                            stack[top, 0], stack[top, 1] = rr, cc
                            top += 1
            n += 1
    return out[:n].copy()


def warm_up() -> None:
    """Compile the grouping kernel on a tiny mask."""
    groups_of_mask(np.eye(3, dtype=np.bool_), 2)


def full(width: int, height: int) -> Window:
    """The whole grid."""
    return (0, 0, width, height)
