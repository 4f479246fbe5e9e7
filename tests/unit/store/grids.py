"""Small maps for the store tests, written as ASCII rows."""

from __future__ import annotations

import numpy as np

from polynav.geometry import Pose2D
from polynav.maps.map import Map, MapInfo


def small_map(rows: list[str], *, resolution: float = 0.1, origin: Pose2D | None = None) -> Map:
    """A map from ASCII rows, top row first: '#' occupied, '.' free, '?' unknown, digits 10*d."""
    values = {"#": 100, ".": 0, "?": -1}
    data = np.array(
        [[values[c] if c in values else 10 * int(c) for c in row] for row in reversed(rows)],
        dtype=np.int8,
    )
    h, w = data.shape
    info = MapInfo(resolution=resolution, width=w, height=h, origin=origin or Pose2D())
    return Map(info, data)


def assert_maps_equal(a: Map, b: Map) -> None:
    assert a.info == b.info
    assert a.data.dtype == b.data.dtype
    np.testing.assert_array_equal(a.data, b.data)
