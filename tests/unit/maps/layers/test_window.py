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


def test_groups_of_mask_split_far_apart_cells_and_cover_every_cell() -> None:
    mask = np.zeros((60, 80), dtype=bool)
    assert win.groups_of_mask(mask, 10) == []
    mask[2:5, 3:6] = True  # one group, near the origin
    mask[6, 8] = True  # within the gap of it: the same group
    mask[50:55, 70:72] = True  # far away: a group of its own
    groups = sorted(win.groups_of_mask(mask, 10))
    assert groups == [(3, 2, 9, 7), (70, 50, 72, 55)]
    covered = np.zeros_like(mask)
    for group in groups:
        covered[win.slices(group)] = True
    assert not (mask & ~covered).any()
    # Close cells stay one window, whatever tile they fall in.
    near = np.zeros((60, 80), dtype=bool)
    near[9, 9] = near[10, 10] = True
    assert win.groups_of_mask(near, 10) == [(9, 9, 11, 11)]
