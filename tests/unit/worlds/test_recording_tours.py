"""Closed tours through shipped floor plans (what the unseen SLAM logs are recorded on)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage

from polynav.errors import InvalidRequest
from polynav.maps.map import FREE
from polynav.robot.sim import recording
from polynav.worlds.tours import plan_tour

DATA = Path(__file__).resolve().parents[3] / "data"


def test_a_tour_is_closed_spaced_and_clear_of_the_walls() -> None:
    tour = plan_tour(DATA / "nav2" / "maps" / "depot.yaml", stops=5, seed=1)
    points = np.array(tour.waypoints)
    assert tour.waypoints[0] == tour.waypoints[-1] == tour.stops[0] == tour.stops[-1]
    assert len(tour.stops) == 5 + 2
    steps = np.hypot(*np.diff(points, axis=0).T)
    assert np.all(steps > 0.0) and np.all(steps <= 0.75 + 1e-9)
    assert tour.length >= float(np.sum(steps)) - 1e-6
    grid = tour.world.floor("floor1").map
    clearance = ndimage.distance_transform_edt(grid.data == FREE) * grid.info.resolution
    ix, iy = grid.info.world_to_cells(points).T
    assert np.all(clearance[iy, ix] >= 0.25 + 0.1)  # the robot's radius and some room
    # Every stop is on the tour.
    for sx, sy in tour.stops:
        assert np.min(np.hypot(points[:, 0] - sx, points[:, 1] - sy)) < 0.2


def test_a_tour_and_its_recording_are_the_same_for_the_same_seed() -> None:
    plan = DATA / "movingai" / "empty-8-8.map"
    a, b = plan_tour(plan, stops=2, seed=4), plan_tour(plan, stops=2, seed=4)
    assert a.waypoints == b.waypoints
    assert plan_tour(plan, stops=2, seed=5).waypoints != a.waypoints
    first = recording.record(a.world, a.waypoints, seed=2, scan_every=5, time_limit=20.0)
    again = recording.record(b.world, b.waypoints, seed=2, scan_every=5, time_limit=20.0)
    assert first.lines == again.lines and len(first.truth) > 20


def test_bad_tours_are_refused_clearly() -> None:
    with pytest.raises(InvalidRequest, match="at least 2 stops"):
        plan_tour(DATA / "movingai" / "empty-8-8.map", stops=1)
    with pytest.raises(InvalidRequest, match="spacing"):
        plan_tour(DATA / "movingai" / "empty-8-8.map", spacing=math.nan)
    with pytest.raises(InvalidRequest, match="no such file"):
        plan_tour(DATA / "movingai" / "no-such.map")
