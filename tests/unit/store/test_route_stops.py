"""Routes with stops (polynav.store.route_stops): the default route, stops as map points,
keepouts mirrored into the map, and nothing written on bad input."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.errors import InvalidRequest, NotFound
from polynav.geometry import Pose2D
from polynav.maps.keepout import ForbiddenZone, VirtualWall
from polynav.site import PointKind
from polynav.store.route_stops import (
    DEFAULT_ROUTE,
    RouteBook,
    StopInput,
    wall_polylines,
)
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world


@pytest.fixture
def book(tmp_path: Path) -> Iterator[RouteBook]:
    with SiteStore.open(tmp_path / "data", seed_world=load_world("demo")) as store:
        yield RouteBook(store)


def test_default_route_is_the_maps_points_without_chargers(book: RouteBook) -> None:
    route = book.route("floor1", DEFAULT_ROUTE)
    names = [p.name for p in book.store.points(map_name="floor1")
             if p.kind is not PointKind.CHARGER]
    assert [s.point for s in route.stops] == names and not route.stored
    assert book.names("floor1") == [DEFAULT_ROUTE]
    with pytest.raises(NotFound):
        book.route("floor1", "nope")


def test_stops_create_reuse_and_drop_points(book: RouteBook) -> None:
    book.set_stops("floor1", "r", [StopInput(Pose2D(5, 10, 0)),
                                   StopInput(Pose2D(5.5, 12.5, 0.3), "lobby")])
    assert book.store.point("floor1", "r_0").pose == Pose2D(5, 10, 0)
    assert book.store.point("floor1", "lobby").pose.theta == pytest.approx(0.3)
    assert [p.name for p in book.stop_points(book.route("floor1", "r"))] == ["r_0", "lobby"]
    book.set_stops("floor1", "r", [StopInput(Pose2D(6, 10, 0), "new")])
    names = {p.name for p in book.store.points(map_name="floor1")}
    assert "r_0" not in names and "new" in names and "lobby" in names
    book.delete("floor1", "r")
    assert "new" not in {p.name for p in book.store.points(map_name="floor1")}


def test_bad_stops_write_nothing(book: RouteBook) -> None:
    before = book.store.points(map_name="floor1")
    with pytest.raises(InvalidRequest):
        book.set_stops("floor1", "r", [StopInput(Pose2D(1, 1, 0), "a"),
                                       StopInput(Pose2D(2, 2, 0), "a")])
    with pytest.raises(InvalidRequest):
        book.set_stops("floor1", "initial", [StopInput(Pose2D(1, 1, 0))] * 2 +
                       [StopInput(Pose2D(float("nan"), 1, 0))])
    with pytest.raises(NotFound):
        book.set_stops("nomap", "r", [StopInput(Pose2D(1, 1, 0))])
    assert book.store.points(map_name="floor1") == before
    assert book.store.routes("floor1") == []


def test_walls_and_areas_are_the_maps_keepouts(book: RouteBook) -> None:
    book.store.set_keepouts("floor1", [VirtualWall(((0.0, 0.0), (1.0, 0.0)))])
    book.set_walls("floor1", "a", [(2.0, 2.0), (2.05, 2.0), (5.0, 5.0)])
    book.set_areas("floor1", "b", [(3.0, 4.0, 1.0, 2.0)])
    keepouts = book.store.keepouts("floor1")
    assert keepouts[0] == VirtualWall(((0.0, 0.0), (1.0, 0.0)))  # the map's own, untouched
    assert VirtualWall(((2.0, 2.0), (2.05, 2.0))) in keepouts
    assert VirtualWall(((5.0, 5.0),)) in keepouts
    assert ForbiddenZone(((1.0, 2.0), (3.0, 2.0), (3.0, 4.0), (1.0, 4.0))) in keepouts
    book.delete("floor1", "a")
    book.set_areas("floor1", "b", [])
    assert book.store.keepouts("floor1") == [VirtualWall(((0.0, 0.0), (1.0, 0.0)))]
    with pytest.raises(InvalidRequest):
        book.set_areas("floor1", "b", [(1.0, 1.0, 1.0, 5.0)])


def test_default_route_keeps_following_the_map_when_it_has_walls(book: RouteBook) -> None:
    book.set_walls("floor1", DEFAULT_ROUTE, [(2.0, 2.0)])
    assert book.route("floor1", DEFAULT_ROUTE).stored
    book.store.delete_point("floor1", "lobby")
    assert "lobby" not in [s.point for s in book.route("floor1", DEFAULT_ROUTE).stops]


def test_wall_points_split_into_polylines_at_gaps() -> None:
    walls = wall_polylines([(0, 0), (0.05, 0), (0.1, 0), (3, 3), (3.05, 3)])
    assert [len(w.points) for w in walls] == [3, 2]
