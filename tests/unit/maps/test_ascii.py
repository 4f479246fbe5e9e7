from __future__ import annotations

import numpy as np
import pytest

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps.ascii import map_from_ascii, map_to_ascii
from polynav.maps.map import MapInfo


def test_first_text_line_is_the_top_row_of_the_map() -> None:
    grid = map_from_ascii(
        """
        #..
        .?.
        """
    )
    assert grid.info == MapInfo(resolution=1.0, width=3, height=2)
    assert grid.data.dtype == np.int8
    assert grid.data.tolist() == [[0, -1, 0], [100, 0, 0]]


def test_resolution_and_origin_place_the_cells_in_the_world() -> None:
    grid = map_from_ascii("#.\n..", resolution=0.5, origin=Pose2D(1.0, 2.0))
    assert grid.info.cell_to_world(0, 1) == (1.25, 2.75)
    assert grid.is_free_at(1.25, 2.25)
    assert not grid.is_free_at(1.25, 2.75)


def test_map_to_ascii_prints_top_row_first_and_round_trips() -> None:
    text = "#..?\n.##.\n...."
    assert map_to_ascii(map_from_ascii(text)) == text


@pytest.mark.parametrize(
    "text",
    ["", "\n  \n", "##\n#", "#x#"],
    ids=["empty", "blank", "ragged", "bad-char"],
)
def test_map_from_ascii_rejects_malformed_text(text: str) -> None:
    with pytest.raises(InvalidRequest):
        map_from_ascii(text)


def test_map_from_ascii_rejects_non_positive_resolution() -> None:
    with pytest.raises(InvalidRequest, match="resolution"):
        map_from_ascii("..", resolution=0.0)
