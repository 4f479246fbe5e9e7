"""The tracker's pose covariance: dead reckoning widens it, a match narrows what it pins."""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.localization import degeneracy
from polynav.localization.uncertainty import PoseCovariance

FLOOR = 0.01
HEADING_FLOOR = math.radians(0.25)


def _covariance() -> PoseCovariance:
    return PoseCovariance(min_position=FLOOR, min_heading=HEADING_FLOOR)


def test_position_uncertainty_grows_linearly_with_dead_reckoned_distance():
    cov = _covariance()
    for _ in range(100):
        cov.predict(0.25, 0.0, drift=0.02, heading_drift=0.02)  # 25 m straight
    assert cov.uncertainty.position == pytest.approx(FLOOR + 0.02 * 25.0)
    assert cov.uncertainty.heading == pytest.approx(HEADING_FLOOR)


def test_heading_uncertainty_grows_with_turning():
    cov = _covariance()
    cov.predict(0.0, -math.pi, drift=0.02, heading_drift=0.02)
    assert cov.uncertainty.heading == pytest.approx(HEADING_FLOOR + 0.02 * math.pi)
    assert cov.uncertainty.position == pytest.approx(FLOOR)


def test_a_room_match_brings_the_uncertainty_back_to_the_floor():
    cov = _covariance()
    cov.reset(0.5, 0.2)
    room = np.diag([60.0, 60.0, 200.0])  # walls all round, endpoints metres away
    con = degeneracy.constraint(room, length_scale=1.0, min_information=4.0)
    cov.correct(con, match_sigma=0.05)
    assert cov.uncertainty.position == pytest.approx(FLOOR)
    assert cov.uncertainty.heading == pytest.approx(HEADING_FLOOR)


def test_a_corridor_match_pins_only_across_the_corridor():
    cov = _covariance()
    cov.reset(0.3, 0.1)
    corridor = np.diag([0.0, 80.0, 150.0])  # along x: nothing to match
    con = degeneracy.constraint(corridor, length_scale=1.0, min_information=4.0)
    cov.correct(con, match_sigma=0.05)
    m = cov.matrix
    assert math.sqrt(m[0, 0]) == pytest.approx(0.3)
    assert math.sqrt(m[1, 1]) == pytest.approx(FLOOR)
    assert cov.uncertainty.position == pytest.approx(0.3)


def test_an_open_hall_match_changes_nothing():
    cov = _covariance()
    cov.reset(0.4, 0.1)
    before = cov.matrix
    hall = np.diag([1.0, 0.5, 2.0])  # a few endpoints on a far pillar
    cov.correct(degeneracy.constraint(hall, length_scale=1.0, min_information=4.0),
                match_sigma=0.05)
    np.testing.assert_allclose(cov.matrix, before)


def test_a_correction_left_for_later_scans_counts_as_known_error():
    cov = _covariance()
    cov.add_offset(0.0, 0.06, 0.0)
    assert cov.uncertainty.position == pytest.approx(math.hypot(FLOOR, 0.06))


def test_dead_reckoning_widens_each_direction_of_a_slanted_corridor_alike():
    cov = _covariance()
    cov.reset(0.3, 0.1)
    c = s = math.sqrt(0.5)
    across = np.array([-s, c, 0.0])  # a corridor along 45 degrees: only across is pinned
    corridor = 80.0 * np.outer(across, across) + np.diag([0.0, 0.0, 150.0])
    cov.correct(degeneracy.constraint(corridor, length_scale=1.0, min_information=4.0),
                match_sigma=0.05)
    cov.predict(1.0, 0.0, drift=0.02, heading_drift=0.02)
    m = cov.matrix[:2, :2]
    along = np.array([c, s])
    assert math.sqrt(along @ m @ along) == pytest.approx(0.3 + 0.02)
    assert math.sqrt(across[:2] @ m @ across[:2]) == pytest.approx(FLOOR + 0.02)
