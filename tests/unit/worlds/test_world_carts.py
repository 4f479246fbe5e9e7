"""Carts and cabins in world files: read with their defaults, bad ones refused with the field."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.worlds import load_world
from polynav.worlds.carts import CartKind, WorldCart, entry_pose
from polynav.worlds.errors import WorldFormatError
from polynav.worlds.world_file import read_world
from tests.unit.worlds.test_world_file import _document, _write


def _with_carts(*carts: dict[str, Any]) -> dict[str, Any]:
    doc = _document()
    doc["carts"] = list(carts)
    return doc


def test_carts_and_cabins_are_read_with_their_defaults(tmp_path: Path) -> None:
    world = read_world(_write(tmp_path, _with_carts(
        {"name": "c1", "floor": "ground", "x": 3.0, "y": 2.0},
        {"name": "k1", "kind": "cabin", "floor": "ground", "x": 2.0, "y": 2.0,
         "theta": math.pi / 2, "length": 1.0, "width": 0.8, "mass": 70.0, "cabin_id": "K-1"},
    )))
    c1, k1 = world.carts
    assert (c1.kind, c1.length, c1.width, c1.mass, c1.cabin_id) == (
        CartKind.CART, 0.9, 0.7, 40.0, None)
    assert k1.kind is CartKind.CABIN and k1.cabin_id == "K-1" and k1.mass == 70.0
    assert world.cart("k1") is k1
    # Heading north: the front legs are the northern ones, 0.5 m ahead of the centre.
    legs = k1.legs()
    assert legs[0] == pytest.approx((1.6, 2.5))
    assert legs[2] == pytest.approx((2.4, 1.5))
    assert k1.clear_width == pytest.approx(0.74)
    # A robot waits behind the back legs, on the axis, facing in.
    wait = entry_pose(k1.pose, k1.length, 0.6)
    assert (wait.x, wait.y, wait.theta) == pytest.approx((2.0, 0.9, math.pi / 2))


@pytest.mark.parametrize(
    ("cart", "field", "words"),
    [
        ({"name": "c", "x": 3.0, "y": 2.0}, "carts[0].floor", "on no floor"),
        ({"name": "c", "floor": "roof", "x": 3.0, "y": 2.0}, "carts[0].floor",
         "no floor 'roof'"),
        ({"name": "c", "floor": "ground", "x": 3.0, "y": 2.0, "kind": "sofa"},
         "carts[0].kind", "not one of"),
        ({"name": "c", "floor": "ground", "x": 3.0, "y": 2.0, "mass": -1.0},
         "carts[0].mass", "must be >= 0"),
        ({"name": "c", "floor": "ground", "x": 3.0, "y": 2.0, "width": 0.0},
         "carts[0].width", "must be > 0"),
        ({"name": "c", "floor": "ground", "x": 3.0, "y": 2.0, "kind": "cabin"},
         "carts[0].cabin_id", "needs the id"),
        ({"name": "c", "floor": "ground", "x": 3.0, "y": 2.0, "cabin_id": "X"},
         "carts[0].cabin_id", "only a cabin"),
        ({"name": "c", "floor": "ground", "y": 2.0}, "carts[0].x", "missing"),
    ],
)
def test_a_bad_cart_is_refused_with_its_field(tmp_path: Path, cart: dict[str, Any],
                                              field: str, words: str) -> None:
    _write(tmp_path, _with_carts(cart))
    with pytest.raises(WorldFormatError) as error:
        read_world(tmp_path)
    assert error.value.field == field
    assert words in error.value.reason


def test_cart_names_must_not_repeat(tmp_path: Path) -> None:
    cart = {"name": "c", "floor": "ground", "x": 3.0, "y": 2.0}
    _write(tmp_path, _with_carts(cart, dict(cart)))
    with pytest.raises(WorldFormatError) as error:
        read_world(tmp_path)
    assert error.value.field == "carts"


def test_a_cart_built_in_code_is_checked_too() -> None:
    with pytest.raises(InvalidRequest, match="on no floor"):
        WorldCart("c", CartKind.CART, "", Pose2D())
    with pytest.raises(InvalidRequest, match="legs wider"):
        WorldCart("c", CartKind.CART, "f", Pose2D(), width=0.05)


def test_the_demo_has_two_carts_in_the_lobby_and_a_cabin_at_its_parking_spot() -> None:
    world = load_world("demo")
    kinds = sorted((c.floor, c.kind.value) for c in world.carts)
    assert kinds == [("floor1", "cart"), ("floor1", "cart"), ("floor2", "cabin")]
    for cart in world.carts:
        # Legs, centre and the waiting pose behind it stand in free space.
        grid = world.floor(cart.floor).map
        occupied, info = grid.occupied(), grid.info
        wait = entry_pose(cart.pose, cart.length, 0.6)
        for x, y in (*cart.legs(), (cart.pose.x, cart.pose.y), (wait.x, wait.y)):
            ix, iy = info.world_to_cell(x, y)
            assert not occupied[iy - 4:iy + 5, ix - 4:ix + 5].any(), (cart.name, x, y)


def test_the_carried_footprint_holds_the_body_and_the_cart() -> None:
    from polynav.footprint import Footprint
    from polynav.worlds.carts import carried_footprint

    body = Footprint.circle(0.25)
    carried = carried_footprint(body, Pose2D(0.02, 0.0, 0.0), 0.9, 0.7)
    assert carried.covers(body)
    assert carried.inscribed_radius == pytest.approx(0.38, abs=1e-6)
    assert carried.circumscribed_radius == pytest.approx(math.hypot(0.5, 0.38), abs=1e-6)
    # A body longer than the cart sticks out of it: the hull keeps it.
    long_body = Footprint.rectangle(1.2, 0.4)
    assert carried_footprint(long_body, Pose2D(), 0.9, 0.7).covers(long_body)
