"""Every route of the native API over real HTTP, with a fake runtime: bodies, statuses, errors."""

from __future__ import annotations

import math

import httpx
import pytest

from polynav.geometry import Pose2D
from polynav.nav.attempt import GoalOptions
from tests.api.fakes import FakeRuntime


def _error(response: httpx.Response, status: int, code: str) -> str:
    assert response.status_code == status, response.text
    body = response.json()
    assert set(body) == {"error"}
    assert set(body["error"]) == {"code", "message"}
    assert body["error"]["code"] == code
    return str(body["error"]["message"])


def test_status_has_exactly_the_contract_keys(client: httpx.Client) -> None:
    body = client.get("/api/status").json()
    assert set(body) == {"mode", "map", "floor", "floor_level", "pose", "velocity", "battery",
                         "estop", "localization", "navigation", "mapping", "stamp", "frame",
                         "links"}
    assert body["links"] == {}  # no serial line served
    assert set(body["pose"]) == {"x", "y", "theta"}
    assert set(body["navigation"]) == {
        "state", "goal", "reason", "distance_remaining", "phase", "retries",
        "arrival_uncertainty"}
    assert set(body["localization"]) == {"state", "quality", "uncertainty"}
    assert body["mode"] == "free"
    assert body["navigation"]["state"] == "idle"
    assert body["mapping"] is None  # not mapping


def test_maps_list_metadata_and_image(client: httpx.Client) -> None:
    maps = client.get("/api/maps").json()
    assert sorted(m["name"] for m in maps) == ["floor1", "floor2", "floor3"]
    one = client.get("/api/maps/floor1").json()
    assert one["floor"] == "floor1"
    assert one["width"] > 0 and one["height"] > 0 and one["resolution"] > 0
    image = client.get("/api/maps/floor1/image.png")
    assert image.status_code == 200
    assert image.headers["content-type"] == "image/png"
    assert image.content[:8] == b"\x89PNG\r\n\x1a\n"


def test_unknown_map_is_404(client: httpx.Client) -> None:
    _error(client.get("/api/maps/nowhere"), 404, "not_found")
    _error(client.get("/api/maps/nowhere/image.png"), 404, "not_found")


def test_points_filter_by_map_and_floor(client: httpx.Client) -> None:
    every = client.get("/api/points").json()
    on1 = client.get("/api/points", params={"map": "floor1"}).json()
    on2 = client.get("/api/points", params={"floor": "floor2"}).json()
    on3 = client.get("/api/points", params={"floor": "floor3"}).json()
    assert len(every) == len(on1) + len(on2) + len(on3)
    assert {p["map"] for p in on1} == {"floor1"}
    assert {p["floor"] for p in on2} == {"floor2"}
    assert set(every[0]) == {"name", "map", "floor", "x", "y", "theta", "kind", "number"}


def test_point_create_update_rename_delete(client: httpx.Client) -> None:
    created = client.post("/api/points", json={"name": "desk", "map": "floor1", "x": 1.5,
                                               "y": 2.0, "theta": 0.5, "kind": "custom"})
    assert created.status_code == 201
    assert created.json() == {"name": "desk", "map": "floor1", "floor": "floor1", "x": 1.5,
                              "y": 2.0, "theta": 0.5, "kind": "custom", "number": None}
    changed = client.put("/api/points/desk", json={"name": "desk2", "x": 3.0})
    assert changed.status_code == 200
    assert (changed.json()["name"], changed.json()["x"], changed.json()["y"]) == ("desk2", 3.0, 2.0)
    _error(client.get("/api/points/desk"), 404, "not_found")
    assert client.get("/api/points/desk2").json()["x"] == 3.0
    assert client.delete("/api/points/desk2").status_code == 204
    _error(client.delete("/api/points/desk2"), 404, "not_found")


def test_point_errors(client: httpx.Client) -> None:
    body = {"name": "dup", "map": "floor1", "x": 1.0, "y": 1.0}
    assert client.post("/api/points", json=body).status_code == 201
    _error(client.post("/api/points", json=body), 409, "conflict")
    _error(client.post("/api/points", json={**body, "map": "nowhere"}), 404, "not_found")
    _error(client.post("/api/points", json={**body, "x": "far"}), 422, "validation_error")
    _error(client.post("/api/points", json={**body, "kind": "sofa"}), 422, "validation_error")
    _error(client.post("/api/points", json={"name": "x"}), 422, "validation_error")
    _error(client.put("/api/points/nothing", json={"x": 1.0}), 404, "not_found")


def test_ambiguous_point_name_needs_its_map(client: httpx.Client) -> None:
    # The demo has "initial" on both floors.
    _error(client.get("/api/points/initial"), 409, "conflict")
    assert client.get("/api/points/initial", params={"map": "floor2"}).json()["map"] == "floor2"


def test_malformed_json_is_400(client: httpx.Client) -> None:
    response = client.post("/api/points", content=b'{"name": ',
                           headers={"content-type": "application/json"})
    _error(response, 400, "malformed_json")
    _error(client.post("/api/navigation/goal", content=b"{nope}",
                       headers={"content-type": "application/json"}), 400, "malformed_json")


def test_navigation_commands_reach_the_runtime(
    client: httpx.Client, fake_runtime: FakeRuntime
) -> None:
    _error(client.post("/api/navigation/goal", json={"point": "initial"}), 409, "conflict")
    assert client.post("/api/navigation/start", json={"map": "floor1"}).json() == {"ok": True}
    assert client.get("/api/status").json()["mode"] == "navigating"
    goal = client.post("/api/navigation/goal", json={"x": 2.0, "y": 1.0, "theta": 0.5})
    assert goal.status_code == 202
    assert goal.json() == {"id": 1}
    status = client.get("/api/status").json()["navigation"]
    assert status["state"] == "running"
    assert status["goal"] == {"x": 2.0, "y": 1.0, "theta": 0.5, "point": None}
    assert client.post("/api/navigation/pause").status_code == 200
    _error(client.post("/api/navigation/pause"), 409, "conflict")
    assert client.post("/api/navigation/resume").status_code == 200
    assert client.post("/api/navigation/cancel").status_code == 200
    _error(client.post("/api/navigation/cancel"), 409, "conflict")
    assert client.get("/api/status").json()["navigation"]["state"] == "canceled"
    assert client.post("/api/navigation/initial_pose",
                       json={"x": 1.0, "y": 2.0, "theta": 3.0}).status_code == 200
    assert fake_runtime.pose == Pose2D(1.0, 2.0, 3.0)
    assert client.post("/api/navigation/stop").status_code == 200
    assert client.get("/api/status").json()["mode"] == "free"
    _error(client.post("/api/navigation/initial_pose", json={"x": 1.0, "y": 2.0}), 409,
           "conflict")


def test_navigation_start_at_a_point(client: httpx.Client, fake_runtime: FakeRuntime) -> None:
    assert client.post("/api/navigation/start",
                       json={"map": "floor2", "point": "initial"}).status_code == 200
    assert fake_runtime.map == "floor2"
    _error(client.post("/api/navigation/start", json={"map": "floor2", "point": "nope"}), 404,
           "not_found")
    _error(client.post("/api/navigation/start", json={"map": "nowhere"}), 404, "not_found")


@pytest.mark.parametrize("body", [
    {}, {"point": "a", "x": 1.0, "y": 2.0}, {"x": 1.0}, {"point": 3}, {"x": "one", "y": 2.0},
    {"point": "a", "speed": 9}, [1, 2],
])
def test_goal_of_the_wrong_shape_is_422(client: httpx.Client, body: object) -> None:
    client.post("/api/navigation/start", json={"map": "floor1"})
    _error(client.post("/api/navigation/goal", json=body), 422, "validation_error")


def test_a_precise_goal_demands_a_position_uncertainty(
    client: httpx.Client, fake_runtime: FakeRuntime
) -> None:
    client.post("/api/navigation/start", json={"map": "floor1"})
    assert client.post("/api/navigation/goal", json={"x": 2.0, "y": 1.0}).status_code == 202
    assert fake_runtime.goal_options is None
    assert client.post("/api/navigation/goal",
                       json={"x": 2.0, "y": 1.0, "precise": True}).status_code == 202
    assert fake_runtime.goal_options == GoalOptions(max_position_uncertainty=0.05)
    assert client.post("/api/navigation/goal",
                       json={"point": "initial", "max_position_uncertainty": 0.02}
                       ).status_code == 202
    assert fake_runtime.goal_options == GoalOptions(max_position_uncertainty=0.02)
    _error(client.post("/api/navigation/goal",
                       json={"x": 2.0, "y": 1.0, "max_position_uncertainty": -1.0}),
           422, "validation_error")


def test_goal_to_unknown_point_is_404_and_other_map_is_409(client: httpx.Client) -> None:
    client.post("/api/navigation/start", json={"map": "floor1"})
    message = _error(client.post("/api/navigation/goal", json={"point": "atlantis"}), 404,
                     "not_found")
    assert "atlantis" in message
    # Well formed, refused by the runtime: a conflict with the current map, not a malformed body.
    _error(client.post("/api/navigation/goal", json={"x": 1.0, "y": 1.0, "map": "floor2"}), 409,
           "invalid_request")


def test_teleop_estop_and_local_move(client: httpx.Client, fake_runtime: FakeRuntime) -> None:
    assert client.post("/api/teleop", json={"linear": 5.0, "angular": -0.5}).status_code == 200
    assert client.get("/api/status").json()["velocity"] == {"linear": 0.6, "angular": -0.5}
    _error(client.post("/api/teleop", json={"linear": "fast"}), 422, "validation_error")
    assert client.post("/api/estop", json={"on": True}).status_code == 200
    assert client.get("/api/status").json()["estop"] == {"hardware": False, "software": True}
    _error(client.post("/api/estop", json={"on": "maybe"}), 422, "validation_error")
    assert client.post("/api/local_move", json={"rotate": 1.5}).status_code == 200
    assert client.post("/api/local_move", json={"distance": -0.5}).status_code == 200
    assert fake_runtime.local_moves == [(1.5, None), (None, -0.5)]
    _error(client.post("/api/local_move", json={"rotate": 1.0, "distance": 1.0}), 422,
           "validation_error")
    _error(client.post("/api/local_move", json={}), 422, "validation_error")


def test_settings_get_and_put(client: httpx.Client) -> None:
    before = client.get("/api/settings").json()
    assert before["max_linear_velocity"] == 0.6
    after = client.put("/api/settings", json={"max_linear_velocity": 0.4})
    assert after.status_code == 200
    assert after.json() == {**before, "max_linear_velocity": 0.4}
    assert client.get("/api/settings").json()["max_linear_velocity"] == 0.4


@pytest.mark.parametrize("changes", [
    {"max_linear_velocity": 50.0}, {"max_linear_velocity": -1}, {"warp": 9},
    {"robot_radius": "big"}, {"robot_radius": True}, {"robot_radius": None},
])
def test_bad_setting_is_422_and_changes_nothing(client: httpx.Client, changes: object) -> None:
    before = client.get("/api/settings").json()
    _error(client.put("/api/settings", json=changes), 422, "validation_error")
    assert client.get("/api/settings").json() == before


@pytest.mark.parametrize("changes", [
    {"obstacle_stop_distance": 1.8}, {"critical_battery_percent": 30.0}, {"led_green": 0.0},
])
def test_setting_that_contradicts_the_others_is_409_and_changes_nothing(
    client: httpx.Client, changes: object
) -> None:
    before = client.get("/api/settings").json()
    _error(client.put("/api/settings", json=changes), 409, "invalid_request")
    assert client.get("/api/settings").json() == before


def test_settings_body_must_be_an_object(client: httpx.Client) -> None:
    _error(client.put("/api/settings", json=[1]), 422, "validation_error")


def test_non_finite_numbers_are_422(client: httpx.Client) -> None:
    response = client.post("/api/teleop", content=b'{"linear": NaN}',
                           headers={"content-type": "application/json"})
    _error(response, 422, "validation_error")
    assert not math.isnan(client.get("/api/status").json()["velocity"]["linear"])


def test_unknown_route_and_method_use_the_error_shape(client: httpx.Client) -> None:
    _error(client.get("/api/nothing"), 404, "not_found")
    _error(client.get("/api/teleop"), 405, "method_not_allowed")


def test_openapi_has_stable_operation_ids(client: httpx.Client) -> None:
    spec = client.get("/openapi.json").json()
    ids = {op["operationId"] for path in spec["paths"].values() for op in path.values()}
    assert {"get_status", "list_maps", "get_map", "get_map_image", "list_points",
            "create_point", "update_point", "delete_point", "start_navigation",
            "stop_navigation", "send_goal", "cancel_goal", "pause_goal", "resume_goal",
            "set_initial_pose", "teleop", "set_estop", "local_move", "get_settings",
            "update_settings"} <= ids
    assert client.get("/docs").status_code == 200
