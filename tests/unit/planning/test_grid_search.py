from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.maps import costs
from polynav.planning import grid_search
from polynav.planning.astar import AStar
from polynav.planning.grid_search import SearchBuffers, check_key_range, step_multipliers


def test_step_multipliers_price_costs_linearly_and_block_from_the_threshold() -> None:
    table = step_multipliers(cost_weight=3.0)
    assert table[costs.FREE] == 1.0
    assert table[126] == pytest.approx(2.5, abs=1e-15)
    assert table[costs.MAX_NON_OBSTACLE] == 4.0
    assert np.isinf(table[costs.INSCRIBED:]).all()
    assert not table.flags.writeable


def test_step_multipliers_price_unknown_when_allowed() -> None:
    table = step_multipliers(cost_weight=2.0, unknown_cost=costs.MAX_NON_OBSTACLE)
    assert table[costs.UNKNOWN] == 3.0
    assert np.isinf(table[costs.INSCRIBED]) and np.isinf(table[costs.LETHAL])


def test_escape_table_opens_only_the_band_below_escape_below() -> None:
    table = step_multipliers(cost_weight=3.0, escape_below=costs.LETHAL)
    assert table[costs.INSCRIBED] == pytest.approx(1.0 + 3.0 * 253 / 252, abs=1e-15)
    assert np.isinf(table[costs.LETHAL]) and np.isinf(table[costs.UNKNOWN])


@pytest.mark.parametrize(
    "kwargs",
    [
        {"cost_weight": -1.0},
        {"cost_weight": math.nan},
        {"cost_weight": math.inf},
        {"cost_weight": 1.0, "lethal_threshold": 0},
        {"cost_weight": 1.0, "lethal_threshold": 257},
        {"cost_weight": 1.0, "unknown_cost": costs.INSCRIBED},
    ],
)
def test_step_multipliers_reject_invalid_arguments(kwargs: dict[str, float]) -> None:
    with pytest.raises(ValueError):
        step_multipliers(**kwargs)  # type: ignore[arg-type]


def test_keys_that_could_overflow_are_refused() -> None:
    check_key_range(step_multipliers(cost_weight=100.0), (2000, 2000))
    with pytest.raises(ValueError):
        check_key_range(step_multipliers(cost_weight=1e6), (2000, 2000))
    with pytest.raises(ValueError):
        AStar().search(np.zeros((300, 300), np.uint8), (0, 0), (1, 1),
                       multipliers=step_multipliers(cost_weight=1e5))


def test_stamps_advance_per_query_and_wrap_by_clearing_the_state() -> None:
    buffers = SearchBuffers()
    assert not buffers.closed(np.array([[0, 0]])).any()
    first = buffers.next_stamp((3, 4), parent_dtype=np.int8)
    assert first == 2 and buffers.next_stamp((3, 4), parent_dtype=np.int8) == 4
    assert buffers.next_stamp((3, 4), parent_dtype=np.int8, stride=4) == 8
    buffers.state[5] = buffers.stamp + 1
    assert buffers.closed(np.array([[1, 1], [0, 0]])).tolist() == [True, False]
    buffers.stamp = grid_search._STAMP_LIMIT - 1
    assert buffers.next_stamp((3, 4), parent_dtype=np.int8) == 2
    assert not buffers.state.any()


def test_a_new_grid_size_reallocates_the_buffers() -> None:
    buffers = SearchBuffers()
    buffers.next_stamp((3, 4), parent_dtype=np.int8)
    assert buffers.g.shape == (12,) and buffers.capacity == 20
    buffers.next_stamp((5, 5), parent_dtype=np.int64)
    assert buffers.g.shape == (25,) and buffers.parent.dtype == np.int64
    buffers.grow_queue()
    assert buffers.capacity == 66 and buffers.heap.shape == (132,)
