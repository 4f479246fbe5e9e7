"""``/api/roslaunch/...`` (puwei-api §5) on the runtime's modes."""

from __future__ import annotations

from tests.protocols.puwei.conftest import MAP, Harness, refused

COVERED = {
    "GET /api/roslaunch/mapping": "test_mapping_starts_the_runtimes_mapping_mode",
    "GET /api/roslaunch/navigation/:name": "test_navigation_starts_on_the_named_map",
    "GET /api/roslaunch/stop": "test_stop_ends_navigation_and_is_a_no_op_when_stopped",
    "GET /api/roslaunch/status": "test_status_is_0_stopped_1_mapping_2_navigating",
}


def test_status_is_0_stopped_1_mapping_2_navigating(puwei: Harness) -> None:
    assert puwei.ok("/api/roslaunch/status") == 0
    puwei.ok("/api/roslaunch/mapping")
    assert puwei.ok("/api/roslaunch/status") == 1
    puwei.ok("/api/roslaunch/stop")
    assert puwei.ok("/api/roslaunch/status") == 0
    puwei.navigate()
    assert puwei.ok("/api/roslaunch/status") == 2


def test_mapping_starts_the_runtimes_mapping_mode(puwei: Harness) -> None:
    assert puwei.ok("/api/roslaunch/mapping") is None
    assert puwei.runtime.status().mode == "mapping"
    # Again while mapping: refused, mapping goes on.
    assert refused(puwei.get("/api/roslaunch/mapping"))["code"] == 4
    assert puwei.runtime.status().mode == "mapping"
    # Navigating refuses while mapping (the map being built would be lost).
    assert refused(puwei.get(f"/api/roslaunch/navigation/{MAP}"))["code"] == 4
    assert puwei.runtime.status().mode == "mapping"


def test_mapping_from_navigation_stops_navigation_first(puwei: Harness) -> None:
    puwei.navigate()
    puwei.ok("/api/roslaunch/mapping")
    assert puwei.runtime.status().mode == "mapping"


def test_navigation_starts_on_the_named_map(puwei: Harness) -> None:
    assert puwei.ok(f"/api/roslaunch/navigation/{MAP}") is None
    assert puwei.advance_until(lambda: puwei.runtime.status().mode == "navigating", 10.0)
    assert puwei.runtime.status().map == MAP


def test_navigation_on_an_unknown_map_is_refused_and_changes_nothing(puwei: Harness) -> None:
    body = refused(puwei.get("/api/roslaunch/navigation/no_such_map"))
    assert body["code"] == 3 and "no_such_map" in body["msg"]
    assert puwei.runtime.status().mode == "free"


def test_stop_ends_navigation_and_is_a_no_op_when_stopped(puwei: Harness) -> None:
    assert puwei.ok("/api/roslaunch/stop") is None
    puwei.navigate()
    puwei.ok("/api/roslaunch/stop")
    assert puwei.advance_until(lambda: puwei.runtime.status().mode == "free", 10.0)
    assert puwei.ok("/api/roslaunch/status") == 0


def test_stop_after_save_keeps_the_map_and_without_save_drops_it(puwei: Harness) -> None:
    before = {m.name for m in puwei.runtime.store.maps()}
    puwei.ok("/api/roslaunch/mapping")
    puwei.runtime.advance(1.0)
    puwei.ok("/api/roslaunch/stop")
    assert {m.name for m in puwei.runtime.store.maps()} == before
    puwei.ok("/api/roslaunch/mapping")
    puwei.runtime.advance(1.0)
    puwei.ok("/api/map/save/lab")
    puwei.ok("/api/roslaunch/stop")
    assert {m.name for m in puwei.runtime.store.maps()} == before | {"lab"}
    assert puwei.runtime.status().mode == "free"
