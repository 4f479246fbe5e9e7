"""Backing up checks the body, not a point behind it: a wall behind and to one side stops
the robot before it touches (a demo robot giving way to a walker backed into a corridor's
wall, bench sim seed 4 on floor 2)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.footprint import Footprint
from polynav.geometry import Pose2D, Twist
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.maps.map import Map, MapInfo
from polynav.nav.recoveries import BackUp

RES = 0.05


def _room() -> Costmap:
    """4 m x 4 m, free, and a wall behind the robot's left: x <= 1.7 m, y >= 2.18 m."""
    data = np.zeros((80, 80), dtype=np.int8)
    for iy in range(80):
        for ix in range(80):
            x, y = (ix + 0.5) * RES, (iy + 0.5) * RES
            if x <= 1.7 and y >= 2.18:
                data[iy, ix] = 100
    return Costmap.from_map(Map(MapInfo(resolution=RES, width=80, height=80), data),
                            CostmapConfig(robot_radius=0.25))


def _back(back_up: BackUp, seconds: float = 6.0) -> Pose2D:
    pose = Pose2D(2.0, 2.0, 0.0)
    back_up.start(pose, 0.0)
    t = 0.0
    while t < seconds:
        twist = back_up.tick(pose, t)
        if twist is None:
            break
        pose = Pose2D(pose.x + twist.linear * math.cos(pose.theta) * 0.05,
                      pose.y + twist.linear * math.sin(pose.theta) * 0.05, pose.theta)
        t += 0.05
    return pose


def _touches_the_wall(pose: Pose2D, radius: float = 0.25) -> bool:
    nearest_x = min(pose.x, 1.7)
    nearest_y = max(pose.y, 2.18)
    return math.hypot(pose.x - nearest_x, pose.y - nearest_y) < radius


def test_the_body_check_stops_before_a_wall_behind_and_aside() -> None:
    costmap = _room()
    probe_only = _back(BackUp(costmap, distance=0.5, speed=0.15, robot_radius=0.25,
                              timeout=8.0))
    assert _touches_the_wall(probe_only)  # the centre-line probe sees nothing
    checked = _back(BackUp(costmap, distance=0.5, speed=0.15, robot_radius=0.25, timeout=8.0,
                           footprint=Footprint.circle(0.25)))
    assert not _touches_the_wall(checked)
    assert checked.x < 2.0  # it did back up, as far as the wall lets it


def _unknown_behind(seen_from: float) -> Costmap:
    """4 m x 4 m, seen free for x >= ``seen_from`` [m], never seen (unknown) behind that."""
    data = np.zeros((80, 80), dtype=np.int8)
    data[:, : round(seen_from / RES)] = -1
    return Costmap.from_map(Map(MapInfo(resolution=RES, width=80, height=80), data),
                            CostmapConfig(robot_radius=0.25, track_unknown=True))


def test_the_back_up_goes_only_onto_floor_seen_free() -> None:
    # Cleared marks behind a robot blind behind are unknown floor to the check, not free: the
    # delivery robot (270 degree lidar) backed into a post after the ladder cleared it.
    body = Footprint.circle(0.25)
    blind = _back(BackUp(_unknown_behind(1.6), distance=0.5, speed=0.15, timeout=8.0,
                         footprint=body))
    assert blind.x - 0.25 >= 1.6 - 1e-9  # the body stopped at the unseen floor
    assert blind.x < 2.0  # having backed onto the floor it had seen
    seen = _back(BackUp(_unknown_behind(0.0), distance=0.2, speed=0.15, timeout=8.0,
                        footprint=body))
    assert seen.x == pytest.approx(1.8, abs=0.01)


def test_the_ladder_s_back_up_stands_for_a_scan_first() -> None:
    back_up = BackUp(_room(), distance=0.2, speed=0.15, timeout=8.0,
                     footprint=Footprint.circle(0.25), settle=0.1)
    pose = Pose2D(2.0, 2.0, 0.0)
    back_up.start(pose, 0.0)
    assert back_up.tick(pose, 0.0) == back_up.tick(pose, 0.05) == Twist()
    twist = back_up.tick(pose, 0.1)
    assert twist is not None and twist.linear < 0.0
