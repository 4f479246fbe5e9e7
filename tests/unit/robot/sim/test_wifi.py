from __future__ import annotations

import numpy as np
import pytest

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps.map import Map, MapInfo
from polynav.robot.sim.wifi import WirelessCard
from polynav.site import Point, PointKind
from polynav.worlds.world import AccessPoint, World, WorldFloor

INFO = MapInfo(resolution=0.1, width=400, height=100, origin=Pose2D(0.0, 0.0, 0.0))


def _world() -> tuple[World, np.ndarray]:
    occupied = np.zeros((100, 400), dtype=bool)
    occupied[:, 200] = True  # a wall at x = 20 m
    data = np.where(occupied, 100, 0).astype(np.int8)
    aps = (
        AccessPoint("home", 5.0, 5.0, 2437, "WPA2", "secret"),
        AccessPoint("home-5G", 5.0, 5.0, 5180, "WPA2", "secret5"),
        AccessPoint("cafe", 30.0, 5.0, 2412, "", ""),
    )
    floors = []
    for level in (1, 2):
        floors.append(WorldFloor(
            name=f"f{level}", level=level, map_name=f"f{level}", map=Map(INFO, data),
            points=(Point("start", f"f{level}", Pose2D(2.0, 5.0, 0.0), PointKind.INITIAL),),
            lift=None, people=(), access_points=aps if level == 1 else (),
        ))
    return World("wifi", tuple(floors), "f1", Pose2D(2.0, 5.0, 0.0)), occupied


def test_signal_falls_with_distance_walls_floors_and_band() -> None:
    world, occupied = _world()
    card = WirelessCard(world)
    near = {n.ssid: n.signal for n in card.scan(1, 6.0, 5.0, occupied, INFO)}
    far = {n.ssid: n.signal for n in card.scan(1, 19.0, 5.0, occupied, INFO)}
    upstairs = {n.ssid: n.signal for n in card.scan(2, 6.0, 5.0, occupied, INFO)}
    mid = {n.ssid: n.signal for n in card.scan(1, 15.0, 5.0, occupied, INFO)}
    assert near["home"] == 100 and mid["home"] > mid["home-5G"]
    assert far["home"] < mid["home"] < near["home"]
    beyond_wall = card.scan(1, 21.0, 5.0, occupied, INFO)
    same_side = card.scan(1, 19.0, 5.0, occupied, INFO)
    signal = {n.ssid: n.signal for n in beyond_wall}
    assert signal["home"] < {n.ssid: n.signal for n in same_side}["home"] - 10
    assert upstairs["home"] < near["home"] - 20  # a floor: 18 dB, 36 points
    assert [n.ssid for n in card.scan(1, 6.0, 5.0, occupied, INFO)][0] == "home"


def test_connect_needs_range_and_the_password_once() -> None:
    world, occupied = _world()
    card = WirelessCard(world, seed=3)
    here = card.scan(1, 6.0, 5.0, occupied, INFO)
    assert card.active(here) is None and card.ip_address(here) == ""
    with pytest.raises(InvalidRequest, match="wrong password"):
        card.connect("home", "guess", here)
    with pytest.raises(InvalidRequest, match="never joined"):
        card.connect("home", None, here)
    card.connect("home", "secret", here)
    assert card.active(here) == "home" and card.ip_address(here).startswith("192.0.2.")
    card.connect("home", None, here)  # remembered
    far = card.scan(5, 39.0, 9.0, occupied, INFO)  # four storeys up
    assert far == [] and card.active(far) is None  # out of range: the connection is gone
    assert card.mac.startswith("02:") and card.mac != WirelessCard(world, seed=4).mac
