from __future__ import annotations

import dataclasses
import math
import threading
from pathlib import Path

import numpy as np
import pytest

from polynav.errors import Conflict, InvalidRequest, NotFound, StorageError
from polynav.geometry import Pose2D
from polynav.maps.keepout import CircleZone, ForbiddenZone, GuidedZone, VirtualWall
from polynav.maps.ros_map import save_map
from polynav.site import Point, PointKind
from polynav.store import ConnectionRecord, FloorRecord, MapRecord, RouteRecord, SiteStore
from polynav.worlds.world import World
from tests.unit.store.grids import assert_maps_equal, small_map

LOBBY = Point("lobby", "floor1", Pose2D(5.5, 12.5, 0.0), PointKind.GENERAL, 3)


def _files(store: SiteStore) -> list[str]:
    return sorted(p.name for p in (store.data_dir / "maps").iterdir())


# ---------------------------------------------------------------- seeding and reopening


def test_fresh_dir_is_seeded_with_the_worlds_floors_maps_and_points(
    demo_store: SiteStore, demo_world: World
) -> None:
    assert demo_store.floors() == [
        FloorRecord("floor1", 1, "floor1"),
        FloorRecord("floor2", 2, "floor2"),
        FloorRecord("floor3", 3, "floor3"),
    ]
    assert [m.name for m in demo_store.maps()] == ["floor1", "floor2", "floor3"]
    for floor in demo_world.floors:
        record = demo_store.map_record(floor.map_name)
        info = floor.map.info
        assert record == MapRecord(
            floor.map_name, floor.name, info.resolution, info.width, info.height, info.origin
        )
        assert_maps_equal(demo_store.load_map(floor.map_name), floor.map)
        assert demo_store.points(map_name=floor.map_name) == list(floor.points)
    assert demo_store.points() == [p for f in demo_world.floors for p in f.points]
    assert len(demo_store.points()) == 56


def test_seeded_points_keep_kinds_and_numbers(demo_store: SiteStore) -> None:
    assert demo_store.point("floor1", "charger") == Point(
        "charger", "floor1", Pose2D(0.8, 14.0, math.pi), PointKind.CHARGER, 2
    )
    lift = demo_store.point("floor2", "lift_1_inside")
    assert (lift.kind, lift.number) == (PointKind.LIFT_INSIDE, 9)
    assert demo_store.point("floor2", "lift_1_outside").kind is PointKind.LIFT_OUTSIDE


def test_seeded_lift_connections_name_each_cars_floors_and_points(demo_store: SiteStore) -> None:
    records = {r.name: r.data for r in demo_store.connections()}
    assert sorted(records) == ["lift_1", "lift_2"]
    one = records["lift_1"]
    assert one["type"] == "lift" and one["car"] == "lift_1"
    assert [s["floor"] for s in one["stops"]] == ["floor1", "floor2", "floor3"]
    assert one["stops"][2] == {"floor": "floor3", "map": "floor3", "outside": "lift_1_outside",
                               "inside": "lift_1_inside", "waiting": {"x": 38.9, "y": 15.6}}
    assert [s["map"] for s in records["lift_2"]["stops"]] == ["floor1", "floor2"]


def test_seeded_map_files_are_ros_maps_with_a_png_picture(demo_store: SiteStore) -> None:
    assert _files(demo_store) == ["floor1-1.png", "floor1-1.yaml", "floor2-2.png", "floor2-2.yaml",
                                  "floor3-3.png", "floor3-3.yaml"]
    assert demo_store.map_image_path("floor2") == demo_store.data_dir / "maps" / "floor2-2.png"
    assert demo_store.map_image_path("floor2").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_reopen_does_not_seed_again_and_keeps_edits(tmp_path: Path, demo_world: World) -> None:
    data = tmp_path / "data"
    with SiteStore.open(data, seed_world=demo_world) as store:
        store.add_point(Point("dock_b", "floor1", Pose2D(1.0, 2.0, 0.5), PointKind.CHARGER, 40))
        store.delete_point("floor2", "room_212")
        store.update_settings({"max_linear_velocity": 0.8})
        files = _files(store)
    with SiteStore.open(data, seed_world=demo_world) as store:
        assert store.point("floor1", "dock_b").number == 40
        with pytest.raises(NotFound):
            store.point("floor2", "room_212")
        assert len(store.points()) == 56
        assert store.settings() == {"max_linear_velocity": 0.8}
        assert _files(store) == files


def test_reopen_does_not_seed_again_when_everything_was_deleted(
    tmp_path: Path, demo_world: World
) -> None:
    data = tmp_path / "data"
    with SiteStore.open(data, seed_world=demo_world) as store:
        for floor in store.floors():
            store.delete_floor(floor.name)
        for record in store.maps():
            store.delete_map(record.name)
    with SiteStore.open(data, seed_world=demo_world) as store:
        assert (store.floors(), store.maps(), store.points()) == ([], [], [])
        assert _files(store) == []


def test_store_without_seed_world_starts_empty_and_seeds_on_a_later_open(
    tmp_path: Path, demo_world: World
) -> None:
    data = tmp_path / "data"
    with SiteStore.open(data) as store:
        assert (store.floors(), store.maps(), store.points(), store.settings()) == ([], [], [], {})
    with SiteStore.open(data, seed_world=demo_world) as store:
        assert len(store.points()) == 56


def test_closed_store_raises_storage_error(empty_store: SiteStore) -> None:
    empty_store.close()
    empty_store.close()
    with pytest.raises(StorageError, match="closed"):
        empty_store.maps()


def test_open_fails_with_storage_error_when_data_dir_is_a_file(tmp_path: Path) -> None:
    (tmp_path / "data").write_text("not a folder")
    with pytest.raises(StorageError):
        SiteStore.open(tmp_path / "data")


# ---------------------------------------------------------------- points


def test_points_filter_by_map_and_by_floor(demo_store: SiteStore) -> None:
    by_map = demo_store.points(map_name="floor2")
    assert len(by_map) == 23
    assert {p.map_name for p in by_map} == {"floor2"}
    assert demo_store.points(floor="floor1") == demo_store.points(map_name="floor1")
    assert demo_store.points(map_name="floor1", floor="floor2") == []


def test_points_filter_by_unknown_map_or_floor_raises_not_found(demo_store: SiteStore) -> None:
    with pytest.raises(NotFound, match="map 'basement' not found"):
        demo_store.points(map_name="basement")
    with pytest.raises(NotFound, match="floor 'floor9' not found"):
        demo_store.points(floor="floor9")


def test_add_point_then_read_it_back(demo_store: SiteStore) -> None:
    new = Point("bin", "floor2", Pose2D(3.25, -1.5, -2.0), PointKind.CUSTOM, None)
    assert demo_store.add_point(new) == new
    assert demo_store.point("floor2", "bin") == new
    assert demo_store.points(map_name="floor2")[-1] == new
    assert demo_store.find_point("bin") == new


def test_a_custom_point_keeps_its_custom_type_and_only_custom_points_have_one(
    demo_store: SiteStore,
) -> None:
    tagged = Point("cart_bay", "floor2", Pose2D(1.0, 1.0, 0.0), PointKind.CUSTOM, 3, 1007)
    demo_store.add_point(tagged)
    assert demo_store.point("floor2", "cart_bay").custom_type == 1007
    moved = dataclasses.replace(tagged, pose=Pose2D(2.0, 1.0, 0.0), custom_type=1008)
    demo_store.update_point("floor2", "cart_bay", moved)
    assert demo_store.point("floor2", "cart_bay") == moved
    desk = Point("desk", "floor2", Pose2D(1.0, 2.0, 0.0), PointKind.FRONT_DESK, 4)
    assert demo_store.add_point(desk) == demo_store.point("floor2", "desk")
    with pytest.raises(InvalidRequest, match="only a custom point"):
        demo_store.add_point(dataclasses.replace(desk, name="desk2", custom_type=1001))
    with pytest.raises(InvalidRequest, match="custom_type"):
        demo_store.add_point(dataclasses.replace(tagged, name="t2", custom_type="x"))  # type: ignore[arg-type]


def test_add_point_with_a_taken_name_raises_conflict(demo_store: SiteStore) -> None:
    duplicate = dataclasses.replace(LOBBY, pose=Pose2D(1.0, 1.0, 0.0))
    with pytest.raises(Conflict, match="already has a point 'lobby'"):
        demo_store.add_point(duplicate)
    assert demo_store.point("floor1", "lobby") == LOBBY


def test_same_point_name_is_allowed_on_another_map(demo_store: SiteStore) -> None:
    other = dataclasses.replace(LOBBY, map_name="floor2")
    demo_store.add_point(other)
    assert demo_store.point("floor2", "lobby") == other


def test_add_point_on_unknown_map_raises_not_found(demo_store: SiteStore) -> None:
    with pytest.raises(NotFound, match="map 'roof' not found"):
        demo_store.add_point(dataclasses.replace(LOBBY, map_name="roof"))


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"name": ""}, "point.name"),
        ({"name": " lobby2"}, "point.name"),
        ({"name": "a\nb"}, "point.name"),
        ({"pose": Pose2D(math.nan, 0.0, 0.0)}, "point.pose"),
        ({"pose": Pose2D(0.0, math.inf, 0.0)}, "point.pose"),
        ({"kind": "general"}, "point.kind"),
        ({"number": 2.5}, "point.number"),
        ({"number": True}, "point.number"),
    ],
)
def test_add_point_rejects_malformed_points(
    demo_store: SiteStore, change: dict[str, object], field: str
) -> None:
    bad = dataclasses.replace(LOBBY, **{"name": "new", **change})  # type: ignore[arg-type]
    with pytest.raises(InvalidRequest) as info:
        demo_store.add_point(bad)
    assert info.value.field == field
    assert len(demo_store.points()) == 56


def test_update_point_renames_and_moves_it_in_place(demo_store: SiteStore) -> None:
    renamed = Point("reception", "floor1", Pose2D(5.0, 12.0, 1.0), PointKind.GATE, 33)
    assert demo_store.update_point("floor1", "lobby", renamed) == renamed
    assert demo_store.point("floor1", "reception") == renamed
    with pytest.raises(NotFound):
        demo_store.point("floor1", "lobby")
    names = [p.name for p in demo_store.points(map_name="floor1")]
    assert names[:4] == ["initial", "charger", "reception", "front_desk"]


def test_update_point_can_move_it_to_another_map(demo_store: SiteStore) -> None:
    moved = dataclasses.replace(LOBBY, map_name="floor2")
    demo_store.update_point("floor1", "lobby", moved)
    assert demo_store.point("floor2", "lobby") == moved
    assert len(demo_store.points(map_name="floor1")) == 17


def test_update_point_onto_a_taken_name_raises_conflict(demo_store: SiteStore) -> None:
    with pytest.raises(Conflict):
        demo_store.update_point("floor1", "lobby", dataclasses.replace(LOBBY, name="kitchen"))
    assert demo_store.point("floor1", "lobby") == LOBBY


def test_update_point_keeping_its_name_is_not_a_conflict(demo_store: SiteStore) -> None:
    changed = dataclasses.replace(LOBBY, pose=Pose2D(6.0, 12.0, 0.25))
    demo_store.update_point("floor1", "lobby", changed)
    assert demo_store.point("floor1", "lobby") == changed


def test_update_or_delete_unknown_point_raises_not_found(demo_store: SiteStore) -> None:
    with pytest.raises(NotFound, match="point 'floor1/nowhere' not found"):
        demo_store.update_point("floor1", "nowhere", LOBBY)
    with pytest.raises(NotFound, match="point 'floor1/nowhere' not found"):
        demo_store.delete_point("floor1", "nowhere")
    with pytest.raises(NotFound, match="map 'roof' not found"):
        demo_store.delete_point("roof", "lobby")
    with pytest.raises(NotFound, match="map 'roof' not found"):
        demo_store.update_point("floor1", "lobby", dataclasses.replace(LOBBY, map_name="roof"))


def test_delete_point_removes_only_that_point(demo_store: SiteStore) -> None:
    demo_store.delete_point("floor1", "initial")
    with pytest.raises(NotFound):
        demo_store.point("floor1", "initial")
    assert demo_store.point("floor2", "initial").pose == Pose2D(36.0, 15.0, math.pi)
    assert len(demo_store.points()) == 55


def test_find_point_is_ambiguous_for_a_name_on_both_floors(demo_store: SiteStore) -> None:
    with pytest.raises(Conflict, match=r"'initial' is on several maps \(floor1, floor2, floor3\)"):
        demo_store.find_point("initial")
    assert demo_store.find_point("initial", map_name="floor2").pose == Pose2D(36.0, 15.0, math.pi)
    assert demo_store.find_point("kitchen").map_name == "floor1"
    assert demo_store.find_point("room_201").map_name == "floor2"


def test_find_point_unknown_raises_not_found(demo_store: SiteStore) -> None:
    with pytest.raises(NotFound, match="point 'nowhere' not found"):
        demo_store.find_point("nowhere")
    with pytest.raises(NotFound):
        demo_store.find_point("kitchen", map_name="floor2")
    with pytest.raises(NotFound, match="map 'roof'"):
        demo_store.find_point("kitchen", map_name="roof")


def test_not_found_is_a_key_error_naming_the_kind(demo_store: SiteStore) -> None:
    with pytest.raises(KeyError) as info:
        demo_store.point("floor1", "nowhere")
    assert isinstance(info.value, NotFound)
    assert info.value.kind == "point"


# ---------------------------------------------------------------- keepouts, routes, connections


def test_keepouts_round_trip_exactly_in_order(demo_store: SiteStore) -> None:
    keepouts = [
        VirtualWall(((1.0, 2.0), (3.1, 4.7), (0.1, 0.2)), 0.15),
        ForbiddenZone(((0.0, 0.0), (1.0 / 3.0, 0.0), (0.5, 2.0))),
        CircleZone(10.5, -2.25, 0.7),
        VirtualWall(((5.0, 5.0),)),
        GuidedZone(((0.0, 0.0), (4.0, 0.0), (4.0, 1.0)), ((2.0, -1.0), (2.0, 2.0)), 0.9,
                   ((2.0, -1.5),), ()),
    ]
    assert demo_store.keepouts("floor1") == []
    demo_store.set_keepouts("floor1", keepouts)
    assert demo_store.keepouts("floor1") == keepouts
    assert demo_store.keepouts("floor2") == []
    demo_store.set_keepouts("floor1", keepouts[2:3])
    assert demo_store.keepouts("floor1") == [CircleZone(10.5, -2.25, 0.7)]
    demo_store.set_keepouts("floor1", [])
    assert demo_store.keepouts("floor1") == []


def test_set_keepouts_rejects_other_values_and_keeps_the_old_ones(demo_store: SiteStore) -> None:
    demo_store.set_keepouts("floor1", [CircleZone(1.0, 1.0, 1.0)])
    with pytest.raises(InvalidRequest):
        demo_store.set_keepouts("floor1", [CircleZone(2.0, 2.0, 1.0), "wall"])  # type: ignore[list-item]
    assert demo_store.keepouts("floor1") == [CircleZone(1.0, 1.0, 1.0)]


def test_keepouts_of_unknown_map_raise_not_found(demo_store: SiteStore) -> None:
    with pytest.raises(NotFound):
        demo_store.keepouts("roof")
    with pytest.raises(NotFound):
        demo_store.set_keepouts("roof", [])


def test_routes_round_trip_per_map(demo_store: SiteStore) -> None:
    route = RouteRecord("patrol", "floor1", {"nodes": [[1.0, 2.0], [3.0, 4.0]], "edges": [[0, 1]]})
    assert demo_store.set_routes("floor1", [route]) == [route]
    assert demo_store.routes("floor1") == [route]
    assert demo_store.routes("floor2") == []
    with pytest.raises(InvalidRequest):
        demo_store.set_routes("floor2", [route])
    with pytest.raises(InvalidRequest):
        demo_store.set_routes("floor1", [route, route])
    with pytest.raises(NotFound):
        demo_store.routes("roof")
    assert demo_store.routes("floor1") == [route]


def test_connections_round_trip(demo_store: SiteStore) -> None:
    lift = ConnectionRecord("lift_1", {"kind": "lift", "points": ["floor1/lift_1_inside"]})
    assert demo_store.set_connections([lift]) == [lift]
    assert demo_store.connections() == [lift]
    with pytest.raises(InvalidRequest):
        demo_store.set_connections([ConnectionRecord("bad", {"x": math.nan})])
    assert demo_store.connections() == [lift]
    demo_store.set_connections([])
    assert demo_store.connections() == []


# ---------------------------------------------------------------- settings


def test_settings_round_trip_and_merge(empty_store: SiteStore) -> None:
    assert empty_store.settings() == {}
    first = empty_store.update_settings({"max_linear_velocity": 0.8, "name": "robot-1"})
    assert first == {"max_linear_velocity": 0.8, "name": "robot-1"}
    merged = empty_store.update_settings({"max_linear_velocity": 1.2, "zones": [1, {"a": None}]})
    assert merged == {"max_linear_velocity": 1.2, "name": "robot-1", "zones": [1, {"a": None}]}
    assert empty_store.settings() == merged


def test_settings_reject_values_that_are_not_json(empty_store: SiteStore) -> None:
    empty_store.update_settings({"a": 1})
    with pytest.raises(InvalidRequest) as info:
        empty_store.update_settings({"b": 2, "c": math.inf})
    assert info.value.field == "settings.c"
    with pytest.raises(InvalidRequest):
        empty_store.update_settings({"d": object()})
    with pytest.raises(InvalidRequest):
        empty_store.update_settings({"": 1})
    assert empty_store.settings() == {"a": 1}


# ---------------------------------------------------------------- maps


def test_save_map_then_load_it_back_exactly(empty_store: SiteStore) -> None:
    grid = small_map(["#..?", "..#.", "?.##"], resolution=0.05, origin=Pose2D(-1.0, 2.5, 0.25))
    record = empty_store.save_map("lab", grid)
    assert record == MapRecord("lab", None, 0.05, 4, 3, Pose2D(-1.0, 2.5, 0.25))
    assert empty_store.maps() == [record]
    assert_maps_equal(empty_store.load_map("lab"), grid)
    assert _files(empty_store) == ["lab-1.png", "lab-1.yaml"]


def test_save_map_keeps_partial_occupancy_exactly(empty_store: SiteStore) -> None:
    grid = small_map(["0123", "4567", "89#?"])
    empty_store.save_map("scan", grid)
    assert_maps_equal(empty_store.load_map("scan"), grid)


def test_overwrite_map_replaces_files_and_keeps_points_and_floor(demo_store: SiteStore) -> None:
    grid = small_map(["..", "#."], resolution=0.5)
    record = demo_store.save_map("floor1", grid)
    assert record == MapRecord("floor1", "floor1", 0.5, 2, 2, Pose2D())
    assert_maps_equal(demo_store.load_map("floor1"), grid)
    assert _files(demo_store) == ["floor1-4.png", "floor1-4.yaml", "floor2-2.png", "floor2-2.yaml",
                                  "floor3-3.png", "floor3-3.yaml"]
    assert len(demo_store.points(map_name="floor1")) == 18
    assert demo_store.floor("floor1").map_name == "floor1"


def test_save_map_on_a_floor(demo_store: SiteStore) -> None:
    record = demo_store.save_map("floor2_new", small_map(["."]), floor="floor2")
    assert record.floor == "floor2"
    assert demo_store.points(floor="floor2") == demo_store.points(map_name="floor2")
    demo_store.add_point(Point("x", "floor2_new", Pose2D()))
    assert [p.name for p in demo_store.points(floor="floor2")][-1] == "x"


def test_save_map_on_unknown_floor_raises_not_found_and_writes_nothing(
    demo_store: SiteStore,
) -> None:
    files = _files(demo_store)
    with pytest.raises(NotFound, match="floor 'floor7'"):
        demo_store.save_map("f7", small_map(["."]), floor="floor7")
    assert _files(demo_store) == files
    assert [m.name for m in demo_store.maps()] == ["floor1", "floor2", "floor3"]


@pytest.mark.parametrize("name", ["", " lab", "lab\t", "x" * 201])
def test_save_map_rejects_bad_names(empty_store: SiteStore, name: str) -> None:
    with pytest.raises(InvalidRequest):
        empty_store.save_map(name, small_map(["."]))
    assert _files(empty_store) == []


def test_map_names_with_any_characters_get_safe_file_names(empty_store: SiteStore) -> None:
    grid = small_map(["#."])
    empty_store.save_map("../一楼 east/..", grid)
    assert _files(empty_store) == ["east-1.png", "east-1.yaml"]
    assert_maps_equal(empty_store.load_map("../一楼 east/.."), grid)


def test_delete_map_deletes_its_files_points_keepouts_and_routes(demo_store: SiteStore) -> None:
    demo_store.save_map("annex", small_map(["..", ".."]), floor="floor1")
    demo_store.add_point(Point("a", "annex", Pose2D(0.1, 0.1, 0.0)))
    demo_store.set_keepouts("annex", [CircleZone(0.1, 0.1, 0.1)])
    demo_store.set_routes("annex", [RouteRecord("r", "annex", [])])
    demo_store.delete_map("annex")
    with pytest.raises(NotFound):
        demo_store.map_record("annex")
    with pytest.raises(NotFound):
        demo_store.load_map("annex")
    with pytest.raises(NotFound):
        demo_store.map_image_path("annex")
    assert demo_store.find_point("kitchen").map_name == "floor1"
    with pytest.raises(NotFound):
        demo_store.find_point("a")
    assert _files(demo_store) == ["floor1-1.png", "floor1-1.yaml", "floor2-2.png", "floor2-2.yaml",
                                  "floor3-3.png", "floor3-3.yaml"]
    # The same name can be used again, starting with nothing on it.
    demo_store.save_map("annex", small_map(["."]))
    assert demo_store.points(map_name="annex") == []
    assert demo_store.keepouts("annex") == []
    assert demo_store.routes("annex") == []


def test_delete_map_of_a_floor_raises_conflict(demo_store: SiteStore) -> None:
    with pytest.raises(Conflict, match="map of floor floor1"):
        demo_store.delete_map("floor1")
    assert len(demo_store.points(map_name="floor1")) == 18


def test_delete_unknown_map_raises_not_found(demo_store: SiteStore) -> None:
    with pytest.raises(NotFound, match="map 'roof' not found"):
        demo_store.delete_map("roof")
    with pytest.raises(NotFound):
        demo_store.load_map("roof")
    with pytest.raises(NotFound):
        demo_store.map_record("roof")


def test_load_map_with_missing_files_raises_storage_error(empty_store: SiteStore) -> None:
    empty_store.save_map("lab", small_map(["#."]))
    empty_store.map_image_path("lab").unlink()
    with pytest.raises(StorageError, match="map 'lab' is damaged"):
        empty_store.load_map("lab")


def test_open_removes_map_files_no_row_names(tmp_path: Path) -> None:
    data = tmp_path / "data"
    with SiteStore.open(data) as store:
        store.save_map("lab", small_map(["#."]))
    maps = data / "maps"
    save_map(small_map(["##"]), maps / "lab-2.yaml")  # a save that crashed before its commit
    (maps / ".lab-3.png.x1y2.tmp").write_bytes(b"half")
    (maps / "notes").mkdir()
    with SiteStore.open(data) as store:
        assert sorted(p.name for p in maps.iterdir()) == ["lab-1.png", "lab-1.yaml", "notes"]
        assert_maps_equal(store.load_map("lab"), small_map(["#."]))
        # The serial of the crashed save is used again, over nothing.
        store.save_map("lab", small_map([".."]))
        assert _files(store) == ["lab-2.png", "lab-2.yaml", "notes"]


# ---------------------------------------------------------------- floors


def test_save_floor_adds_a_floor_and_attaches_its_map(demo_store: SiteStore) -> None:
    demo_store.save_map("basement", small_map(["."]))
    record = FloorRecord("basement", -1, "basement")
    assert demo_store.save_floor(record) == record
    assert demo_store.floors()[0] == record
    assert demo_store.map_record("basement").floor == "basement"
    demo_store.save_floor(FloorRecord("basement", -2, "basement"))
    assert demo_store.floor("basement").level == -2


def test_save_floor_with_unknown_map_raises_not_found(demo_store: SiteStore) -> None:
    with pytest.raises(NotFound, match="map 'nope'"):
        demo_store.save_floor(FloorRecord("floor4", 4, "nope"))
    with pytest.raises(NotFound):
        demo_store.floor("floor4")


def test_delete_floor_leaves_its_maps_without_a_floor(demo_store: SiteStore) -> None:
    demo_store.delete_floor("floor2")
    assert demo_store.map_record("floor2").floor is None
    assert [f.name for f in demo_store.floors()] == ["floor1", "floor3"]
    with pytest.raises(NotFound):
        demo_store.delete_floor("floor2")


# ---------------------------------------------------------------- threads


def test_concurrent_writers_from_threads_all_land(empty_store: SiteStore) -> None:
    empty_store.save_map("lab", small_map(["."]))
    errors: list[BaseException] = []

    def writer(k: int) -> None:
        try:
            for i in range(25):
                empty_store.add_point(Point(f"t{k}-{i}", "lab", Pose2D(float(i), float(k), 0.0)))
                empty_store.points(map_name="lab")
        except BaseException as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=writer, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    points = empty_store.points(map_name="lab")
    assert len(points) == 100
    for k in range(4):
        mine = [p for p in points if p.name.startswith(f"t{k}-")]
        assert [p.pose.x for p in mine] == [float(i) for i in range(25)]


def test_two_stores_on_one_dir_see_each_others_writes(tmp_path: Path) -> None:
    with SiteStore.open(tmp_path / "d") as a, SiteStore.open(tmp_path / "d") as b:
        a.save_map("lab", small_map(["."]))
        b.add_point(Point("p", "lab", Pose2D(1.0, 2.0, 3.0)))
        assert a.point("lab", "p").pose == Pose2D(1.0, 2.0, 3.0)
        b.save_map("lab", small_map(["#"]))
        assert np.array_equal(a.load_map("lab").data, np.array([[100]], dtype=np.int8))


def test_failed_seeding_leaves_nothing_and_seeds_on_the_next_open(
    tmp_path: Path, demo_world: World, monkeypatch: pytest.MonkeyPatch
) -> None:
    from polynav.maps import ros_map

    real_save = ros_map.save_map
    calls: list[Path] = []

    def fail_second(grid: object, path: Path, **kwargs: object) -> None:
        calls.append(Path(path))
        if len(calls) == 2:
            raise StorageError("disk full")
        real_save(grid, path, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(ros_map, "save_map", fail_second)
    data = tmp_path / "data"
    with pytest.raises(StorageError, match="disk full"):
        SiteStore.open(data, seed_world=demo_world)
    assert sorted(p.name for p in (data / "maps").iterdir()) == []
    monkeypatch.setattr(ros_map, "save_map", real_save)
    with SiteStore.open(data, seed_world=demo_world) as store:
        assert len(store.points()) == 56
        assert [m.name for m in store.maps()] == ["floor1", "floor2", "floor3"]
