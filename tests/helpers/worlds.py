"""Small worlds for mapping tests: quick to explore, with features for the SLAM to hold on to."""

from __future__ import annotations

import numpy as np

from polynav.geometry import Pose2D
from polynav.maps.map import Map, MapInfo
from polynav.site import Point, PointKind
from polynav.worlds.world import World, WorldFloor

RES = 0.05
TWO_ROOMS_START = Pose2D(2.5, 3.0, 0.0)


def two_rooms() -> World:
    """Two 6 x 6 m rooms joined by a 1.2 m door, a pillar or two in each; the robot starts in
    the west room."""
    width, height = int(12.0 / RES), int(6.0 / RES)
    data = np.zeros((height, width), dtype=np.int8)
    data[:4, :] = data[-4:, :] = data[:, :4] = data[:, -4:] = 100
    mid = int(6.0 / RES)
    data[:, mid - 2: mid + 2] = 100
    data[int(2.4 / RES): int(3.6 / RES), mid - 2: mid + 2] = 0  # a 1.2 m door
    for x, y in ((1.0, 1.0), (4.5, 5.0), (8.0, 1.2), (10.8, 4.6)):
        ix, iy = int(x / RES), int(y / RES)
        data[iy - 6: iy + 6, ix - 6: ix + 6] = 100
    grid = Map(MapInfo(RES, width, height), data)
    points = (Point("initial", "f", TWO_ROOMS_START, PointKind.INITIAL),)
    return World("two_rooms", (WorldFloor("f", 1, "f", grid, points, None, ()),), "f",
                 TWO_ROOMS_START)
