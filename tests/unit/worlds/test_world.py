from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps.map import Map
from polynav.site import Point
from polynav.worlds.world import LiftShaft, PersonRoute, World, WorldFloor


def _floor(name: str) -> WorldFloor:
    grid = Map.from_occupied(np.zeros((4, 4), dtype=bool), resolution=0.5)
    return WorldFloor(
        name=name, level=1, map_name=f"map_{name}", map=grid,
        points=(Point("desk", f"map_{name}", Pose2D(1.0, 1.0, 0.0)),), lift=None, people=(),
    )


def test_floor_and_point_are_found_by_name() -> None:
    world = World("w", (_floor("a"), _floor("b")), "a", Pose2D())
    assert world.floor("b").name == "b"
    assert world.floor("b").point("desk").map_name == "map_b"


def test_unknown_floor_or_point_is_an_invalid_request() -> None:
    world = World("w", (_floor("a"),), "a", Pose2D())
    with pytest.raises(InvalidRequest) as floor_error:
        world.floor("attic")
    assert floor_error.value.field == "floor"
    with pytest.raises(InvalidRequest) as point_error:
        world.floor("a").point("bar")
    assert point_error.value.field == "point"


def test_lift_shaft_is_centred_on_its_position() -> None:
    lift = LiftShaft(x=10.0, y=5.0, width=2.0, depth=1.0, door_heading=-math.pi / 2)
    assert lift.bounds == (9.0, 4.5, 11.0, 5.5)
    assert lift.contains(10.9, 5.4)
    assert not lift.contains(11.1, 5.0)
    assert not lift.contains(10.0, 5.6)


@pytest.mark.parametrize(
    ("waypoints", "speed", "radius", "field"),
    [(((0.0, 0.0),), 1.0, 0.25, "waypoints"), (((0.0, 0.0), (1.0, 0.0)), 0.0, 0.25, "speed"),
     (((0.0, 0.0), (1.0, 0.0)), 1.0, -0.1, "radius")],
)
def test_person_route_rejects_degenerate_values(
    waypoints: tuple[tuple[float, float], ...], speed: float, radius: float, field: str
) -> None:
    with pytest.raises(InvalidRequest) as error:
        PersonRoute(waypoints=waypoints, speed=speed, radius=radius)
    assert error.value.field == field
