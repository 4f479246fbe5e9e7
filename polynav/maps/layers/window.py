"""Window arithmetic for the layered costmap: union, growth, clipping, and the window of a mask.

A window is ``(ix0, iy0, ix1, iy1)``, half-open (:data:`polynav.maps.interface.Window`); ``None``
means "nothing changed".
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy import ndimage

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
    whole = of_mask(mask)
    if whole is None:
        return []
    t = max(int(gap), 1)
    h, w = mask.shape
    rows, cols = -(-h // t), -(-w // t)
    tiles = np.zeros((rows * t, cols * t), dtype=np.bool_)
    tiles[:h, :w] = mask
    occupied = tiles.reshape(rows, t, cols, t).any(axis=(1, 3))
    labels, count = ndimage.label(occupied, structure=np.ones((3, 3), dtype=np.bool_))
    if count <= 1:
        return [whole]
    out = []
    for box in ndimage.find_objects(labels):
        y0, x0 = box[0].start * t, box[1].start * t
        part = of_mask(mask[y0:box[0].stop * t, x0:box[1].stop * t])
        if part is not None:
            out.append((part[0] + x0, part[1] + y0, part[2] + x0, part[3] + y0))
    return out


def full(width: int, height: int) -> Window:
    """The whole grid."""
    return (0, 0, width, height)
