from __future__ import annotations

import numpy as np

from polynav.maps.layers import window as win


def test_union_treats_none_as_empty() -> None:
    assert win.union(None, None) is None
    assert win.union(None, (1, 2, 3, 4)) == (1, 2, 3, 4)
    assert win.union((1, 2, 3, 4), (0, 3, 2, 9)) == (0, 2, 3, 9)


def test_clip_cuts_to_the_grid_and_drops_empty_windows() -> None:
    assert win.clip((-3, -1, 50, 4), 10, 8) == (0, 0, 10, 4)
    assert win.clip((12, 0, 15, 3), 10, 8) is None
    assert win.clip(None, 10, 8) is None


def test_grow_adds_cells_on_every_side_within_the_grid() -> None:
    assert win.grow((2, 3, 4, 5), 2, 10, 6) == (0, 1, 6, 6)


def test_of_mask_is_the_bounding_window_of_true_cells() -> None:
    mask = np.zeros((5, 6), dtype=bool)
    assert win.of_mask(mask) is None
    mask[1, 4] = mask[3, 2] = True
    assert win.of_mask(mask) == (2, 1, 5, 4)


def test_slices_index_rows_by_y_and_columns_by_x() -> None:
    grid = np.arange(20).reshape(4, 5)
    assert grid[win.slices((1, 2, 3, 4))].tolist() == [[11, 12], [16, 17]]
