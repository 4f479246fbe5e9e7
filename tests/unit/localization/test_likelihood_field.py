from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.localization.likelihood_field import build_likelihood_field, coarse_likelihood
from polynav.maps.ascii import map_from_ascii

WALL = """
    ##......
    ##......
    ##......
"""


def test_distance_is_zero_on_the_wall_face_and_signed():
    field = build_likelihood_field(map_from_ascii(WALL, resolution=0.1), sigma=0.05,
                                   max_distance=0.5)
    row = field.distance[1]
    # Cell centres: the face is at x = 0.2; occupied centres at 0.05, 0.15, free from 0.25.
    assert row.tolist() == pytest.approx([-0.15, -0.05, 0.05, 0.15, 0.25, 0.35, 0.45, 0.5],
                                         abs=1e-6)
    # Interpolated halfway between the two centres around the face, the distance is zero.
    assert 0.5 * (row[1] + row[2]) == pytest.approx(0.0, abs=1e-7)


def test_likelihood_is_gaussian_in_the_distance():
    field = build_likelihood_field(map_from_ascii(WALL, resolution=0.1), sigma=0.05)
    expected = math.exp(-(0.15**2) / (2 * 0.05**2))
    assert float(field.likelihood[0, 3]) == pytest.approx(expected, rel=1e-5)
    assert float(field.likelihood[0, 2]) == pytest.approx(math.exp(-0.5), rel=1e-5)


def test_distance_is_capped_at_max_distance():
    field = build_likelihood_field(map_from_ascii(WALL, resolution=0.1), max_distance=0.2)
    assert float(field.distance.max()) == pytest.approx(0.2)
    assert float(field.distance.min()) == pytest.approx(-0.15)


def test_map_without_obstacles_is_far_everywhere():
    field = build_likelihood_field(map_from_ascii("....\n....", resolution=0.1),
                                   max_distance=0.3)
    assert np.all(field.distance == np.float32(0.3))


def test_coarse_likelihood_never_underrates_a_neighbour():
    field = build_likelihood_field(map_from_ascii(WALL, resolution=0.1))
    pooled = coarse_likelihood(field, 2)
    assert pooled.shape == field.likelihood.shape
    assert np.all(pooled >= field.likelihood)
    # Cell 4 is 2 cells from cell 2, the best free cell.
    assert float(pooled[1, 4]) == pytest.approx(float(field.likelihood[1, 2]))
    assert float(pooled[1, 5]) == pytest.approx(float(field.likelihood[1, 3]))


def test_rejects_non_positive_sigma():
    with pytest.raises(ValueError, match="sigma"):
        build_likelihood_field(map_from_ascii(WALL, resolution=0.1), sigma=0.0)
