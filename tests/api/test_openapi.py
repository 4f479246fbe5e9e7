"""The OpenAPI document says exactly what the server does: one test per defect class Schemathesis
found (a 500 from an oversized integer, undeclared 4xx answers, schema-valid requests refused
with 422, 405 without ``Allow``), over real HTTP with the fake runtime."""

from __future__ import annotations

import re
from typing import Any

import httpx
import pytest

from polynav.api.schemas import MAX_INTEGER

# What each operation can answer besides its success (500 is declared everywhere: a fault of the
# server, never of the input).
DECLARED: dict[str, set[str]] = {
    "get_status": {"200", "500"},
    "get_diagnostics": {"200", "500"},
    "list_maps": {"200", "500"},
    "get_map": {"200", "404", "422", "500"},
    "get_map_image": {"200", "404", "422", "500"},
    "list_points": {"200", "404", "422", "500"},
    "create_point": {"201", "400", "404", "409", "422", "500"},
    "get_point": {"200", "404", "409", "422", "500"},
    "update_point": {"200", "400", "404", "409", "422", "500"},
    "delete_point": {"204", "404", "409", "422", "500"},
    "start_navigation": {"200", "400", "404", "409", "422", "500"},
    "stop_navigation": {"200", "409", "500"},
    "set_initial_pose": {"200", "400", "409", "422", "500"},
    "send_goal": {"202", "400", "404", "409", "422", "500"},
    "cancel_goal": {"200", "409", "500"},
    "pause_goal": {"200", "409", "500"},
    "resume_goal": {"200", "409", "500"},
    "relocalize": {"200", "409", "500"},
    "start_mapping": {"200", "400", "404", "409", "422", "500"},
    "get_mapping_map": {"200", "409", "500"},
    "get_mapping_map_image": {"200", "409", "500"},
    "save_mapping": {"202", "400", "409", "422", "500"},
    "stop_mapping": {"202", "400", "409", "422", "500"},
    "get_mapping_job": {"200", "404", "422", "500"},
    "cancel_mapping": {"200", "409", "500"},
    "explore": {"200", "409", "500"},
    "teleop": {"200", "400", "409", "422", "500"},
    "set_estop": {"200", "400", "409", "422", "500"},
    "local_move": {"200", "400", "409", "422", "500"},
    "get_settings": {"200", "500"},
    "update_settings": {"200", "400", "409", "422", "500"},
    "get_fleet": {"200", "500"},
    "list_lifts": {"200", "500"},
    "request_lift": {"200", "400", "404", "409", "422", "500"},
    "set_lift_mode": {"200", "400", "404", "409", "422", "500"},
    "list_doors": {"200", "500"},
    "list_carts": {"200", "500"},
    "dock_cart": {"200", "400", "404", "409", "422", "500"},
    "leave_cart": {"200", "400", "404", "409", "422", "500"},
    "cancel_cart_action": {"200", "500"},
    "open_door": {"200", "404", "422", "500"},
    "close_door": {"200", "404", "422", "500"},
    "get_robot": {"200", "500"},
    "start_mapless_navigation": {"200", "409", "500"},
    "check_robot_profile": {"200", "400", "409", "422", "500"},
    "list_tasks": {"200", "404", "422", "500"},
    "create_task": {"201", "400", "404", "409", "422", "500"},
    "trigger_task": {"200", "404", "409", "422", "500"},
    "get_task": {"200", "404", "422", "500"},
    "replace_task": {"200", "400", "404", "409", "422", "500"},
    "delete_task": {"204", "404", "409", "422", "500"},
    "start_task": {"200", "404", "409", "422", "500"},
    "pause_task": {"200", "404", "409", "422", "500"},
    "resume_task": {"200", "404", "409", "422", "500"},
    "cancel_task": {"200", "404", "409", "422", "500"},
    "set_task_loop": {"200", "400", "404", "409", "422", "500"},
    "list_schedules": {"200", "404", "422", "500"},
    "create_schedule": {"201", "400", "404", "409", "422", "500"},
    "get_schedule": {"200", "404", "422", "500"},
    "update_schedule": {"200", "400", "404", "409", "422", "500"},
    "delete_schedule": {"204", "404", "409", "422", "500"},
    "get_scene": {"200", "500"},
    "list_keepouts": {"200", "404", "422", "500"},
    "replace_keepouts": {"200", "400", "404", "409", "422", "500"},
    "add_keepout": {"201", "400", "404", "409", "422", "500"},
    "list_paths": {"200", "404", "422", "500"},
    "save_path": {"200", "400", "404", "409", "422", "500"},
    "delete_path": {"204", "404", "422", "500"},
}


def _operations(spec: dict[str, Any]) -> dict[str, tuple[str, str, dict[str, Any]]]:
    return {
        op["operationId"]: (path, method, op)
        for path, item in spec["paths"].items()
        for method, op in item.items()
    }


def _declares(client: httpx.Client, method: str, path: str, status: int) -> bool:
    """Whether the document declares ``status`` for the operation at this (concrete) path."""
    spec = client.get("/openapi.json").json()
    for template, item in spec["paths"].items():
        pattern = "^" + re.sub(r"\\{[^/]+\\}", "[^/]+", re.escape(template)) + "$"
        if re.match(pattern, path) and method.lower() in item:
            return str(status) in item[method.lower()]["responses"]
    raise AssertionError(f"{method} {path} is not in the document")


@pytest.fixture
def spec(client: httpx.Client) -> dict[str, Any]:
    return dict(client.get("/openapi.json").json())


def _error(response: httpx.Response, status: int, code: str) -> str:
    assert response.status_code == status, response.text
    assert set(response.json()["error"]) == {"code", "message"}
    assert response.json()["error"]["code"] == code
    return str(response.json()["error"]["message"])


def test_every_operation_declares_exactly_the_codes_it_answers(spec: dict[str, Any]) -> None:
    operations = _operations(spec)
    assert set(operations) == set(DECLARED)
    for operation_id, (_, _, op) in operations.items():
        assert set(op["responses"]) == DECLARED[operation_id], operation_id


def test_every_error_answer_is_the_error_model(spec: dict[str, Any]) -> None:
    error = spec["components"]["schemas"]["ErrorOut"]
    assert error["required"] == ["error"]
    detail = spec["components"]["schemas"]["ErrorDetail"]
    assert set(detail["required"]) == {"code", "message"}
    assert "HTTPValidationError" not in spec["components"]["schemas"]
    for operation_id, (_, _, op) in _operations(spec).items():
        for status, answer in op["responses"].items():
            if int(status) >= 400:
                schema = answer["content"]["application/json"]["schema"]
                assert schema == {"$ref": "#/components/schemas/ErrorOut"}, (operation_id, status)


@pytest.mark.parametrize(("method", "path", "body", "status"), [
    ("POST", "/api/points", b'{"name": ', 400),
    ("POST", "/api/points", {"name": "p", "map": "nowhere", "x": 0.0, "y": 0.0}, 404),
    ("POST", "/api/points", {"name": "initial", "map": "floor1", "x": 0.0, "y": 0.0}, 409),
    ("POST", "/api/points", {"name": "p", "map": "floor1", "x": "0", "y": 0.0}, 422),
    ("GET", "/api/points/initial", None, 409),
    ("GET", "/api/points", {"map": "nowhere"}, 404),
    ("GET", "/api/points", {"floor": "nowhere"}, 404),
    ("GET", "/api/maps/nowhere", None, 404),
    ("GET", "/api/maps/nowhere/image.png", None, 404),
    ("PUT", "/api/points/nowhere", {"x": 1.0}, 404),
    ("DELETE", "/api/points/initial", None, 409),
    ("POST", "/api/navigation/goal", {"point": "lobby"}, 409),
    ("POST", "/api/navigation/start", {"map": "nowhere"}, 404),
    ("POST", "/api/navigation/cancel", None, 409),
    ("POST", "/api/navigation/initial_pose", {"x": 1.0, "y": 1.0}, 409),
    ("POST", "/api/localization/relocalize", None, 409),
    ("POST", "/api/mapping/stop", {"name": "new"}, 409),
    ("GET", "/api/mapping/jobs/7", None, 404),
    ("POST", "/api/mapping/cancel", None, 409),
    ("GET", "/api/mapping/map", None, 409),
    ("POST", "/api/teleop", b"{", 400),
    ("PUT", "/api/settings", {"led_green": 0.0}, 409),
    ("PUT", "/api/settings", b"[", 400),
])
def test_each_answer_the_server_gives_is_declared(
    client: httpx.Client, method: str, path: str, body: object, status: int
) -> None:
    if isinstance(body, bytes):
        response = client.request(method, path, content=body,
                                  headers={"content-type": "application/json"})
    elif method == "GET":
        response = client.request(method, path, params=body)  # type: ignore[arg-type]
    else:
        response = client.request(method, path, json=body)
    assert response.status_code == status, response.text
    assert _declares(client, method, path, status)


@pytest.mark.parametrize("number", [2**63, -(2**63) - 1, 10**30, MAX_INTEGER + 1])
def test_oversized_point_number_is_422_not_500(client: httpx.Client, number: int) -> None:
    body = {"name": "big", "map": "floor1", "x": 0.0, "y": 0.0, "number": number}
    _error(client.post("/api/points", json=body), 422, "validation_error")
    assert client.post("/api/points", json={**body, "number": 7}).status_code == 201
    _error(client.put("/api/points/big", json={"number": number}), 422, "validation_error")
    assert client.get("/api/points/big").json()["number"] == 7


def test_point_number_at_the_bound_round_trips_and_the_schema_says_the_bound(
    client: httpx.Client, spec: dict[str, Any]
) -> None:
    body = {"name": "edge", "map": "floor1", "x": 0.0, "y": 0.0, "number": -MAX_INTEGER}
    assert client.post("/api/points", json=body).json()["number"] == -MAX_INTEGER
    assert client.put("/api/points/edge", json={"number": 12.0}).json()["number"] == 12
    number = spec["components"]["schemas"]["PointIn"]["properties"]["number"]["anyOf"][0]
    assert (number["type"], number["minimum"], number["maximum"]) == (
        "integer", -MAX_INTEGER, MAX_INTEGER)
    assert MAX_INTEGER < 2**63


@pytest.mark.parametrize("name", [
    "a\x00b", "tab\there", "new\nline", "del\x7f", "c1\x85", " padded", "padded ", "ide\u3000",
    "a/b", ".", "..", "", "x" * 201,
])
def test_bad_name_is_422_and_the_schema_says_so(
    client: httpx.Client, spec: dict[str, Any], name: str
) -> None:
    body = {"name": name, "map": "floor1", "x": 0.0, "y": 0.0}
    _error(client.post("/api/points", json=body), 422, "validation_error")
    _error(client.put("/api/points/initial", params={"map": "floor1"}, json={"name": name}), 422,
           "validation_error")
    _error(client.get("/api/points", params={"map": name}), 422, "validation_error")
    schema = spec["components"]["schemas"]["PointIn"]["properties"]["name"]
    refused_by_schema = (
        not schema["minLength"] <= len(name) <= schema["maxLength"]
        or re.search(schema["pattern"], name) is None
        or name in schema["not"]["enum"]
    )
    assert refused_by_schema


def test_control_character_in_a_path_name_is_422(client: httpx.Client) -> None:
    _error(client.get("/api/points/a%01b"), 422, "validation_error")
    _error(client.get("/api/maps/floor%7F1"), 422, "validation_error")
    _error(client.delete("/api/points/%20initial"), 422, "validation_error")


@pytest.mark.parametrize("name", ["desk 2", "café", "Ω", "a.b", "...", "x" * 200])
def test_good_names_are_accepted(client: httpx.Client, name: str) -> None:
    body = {"name": name, "map": "floor1", "x": 0.0, "y": 0.0}
    assert client.post("/api/points", json=body).status_code == 201
    assert client.get(f"/api/points/{name}").json()["name"] == name


def test_tiny_floats_are_poses_and_huge_ones_are_out_of_range(client: httpx.Client) -> None:
    tiny = {"name": "tiny", "map": "floor1", "x": 5e-324, "y": -2.2e-308, "theta": 1e-300}
    created = client.post("/api/points", json=tiny)
    assert created.status_code == 201, created.text
    assert created.json()["x"] == 5e-324
    for field, value in (("x", 1e300), ("y", -1.0e6 - 1.0), ("theta", 7.0)):
        _error(client.post("/api/points", json={**tiny, "name": "huge", field: value}), 422,
               "validation_error")
    client.post("/api/navigation/start", json={"map": "floor1"})
    _error(client.post("/api/navigation/initial_pose", json={"x": 1e308, "y": 0.0}), 422,
           "validation_error")
    _error(client.post("/api/navigation/goal", json={"x": 0.0, "y": -1e308}), 422,
           "validation_error")
    assert client.post("/api/navigation/goal", json={"x": 5e-324, "y": 0.0}).status_code == 202


@pytest.mark.parametrize(("path", "body"), [
    ("/api/points", {"name": "p", "map": "floor1", "x": "1.5", "y": 0.0}),
    ("/api/points", {"name": "p", "map": "floor1", "x": 1.0, "y": 0.0, "number": "7"}),
    ("/api/points", {"name": "p", "map": "floor1", "x": 1.0, "y": 0.0, "number": True}),
    ("/api/estop", {"on": "true"}),
    ("/api/estop", {"on": 1}),
    ("/api/teleop", {"linear": True}),
])
def test_numbers_and_booleans_are_strict_as_the_schema_says(
    client: httpx.Client, path: str, body: object
) -> None:
    _error(client.post(path, json=body), 422, "validation_error")


def test_local_move_limits_are_in_the_schema(
    client: httpx.Client, spec: dict[str, Any]
) -> None:
    props = spec["components"]["schemas"]["LocalMoveIn"]["properties"]
    assert props["distance"]["anyOf"][0]["maximum"] == 10.0
    _error(client.post("/api/local_move", json={"distance": 10.5}), 422, "validation_error")
    _error(client.post("/api/local_move", json={"rotate": 13.0}), 422, "validation_error")
    assert client.post("/api/local_move", json={"distance": -10.0}).status_code == 200


def test_settings_schema_carries_every_range(spec: dict[str, Any]) -> None:
    from polynav.runtime.settings import SETTING_RANGES

    settings_in = spec["components"]["schemas"]["SettingsIn"]
    assert settings_in["additionalProperties"] is False
    assert "required" not in settings_in
    ranges = {key: (p["minimum"], p["maximum"]) for key, p in settings_in["properties"].items()}
    assert ranges == SETTING_RANGES


# FastAPI routes serve HEAD only where they declare it (none do), so Allow names no HEAD.
@pytest.mark.parametrize(("method", "path", "allow"), [
    ("PATCH", "/api/points/desk", "DELETE, GET, PUT"),
    ("POST", "/api/points/desk", "DELETE, GET, PUT"),
    ("DELETE", "/api/points", "GET, POST"),
    ("POST", "/api/maps", "GET"),
    ("HEAD", "/api/maps", "GET"),
    ("OPTIONS", "/api/status", "GET"),
    ("PUT", "/api/maps/floor1/image.png", "GET"),
    ("GET", "/api/teleop", "POST"),
    ("DELETE", "/api/settings", "GET, PUT"),
])
def test_405_lists_every_method_of_the_path_in_allow(
    client: httpx.Client, method: str, path: str, allow: str
) -> None:
    response = client.request(method, path)
    assert response.status_code == 405
    if method != "HEAD":
        _error(response, 405, "method_not_allowed")
    assert response.headers["allow"] == allow


def test_apps_share_one_built_document_each_with_its_own_copy(fake_runtime: Any) -> None:
    """The document is built once per process and login setting (it costs pydantic ~0.5 s),
    and each app answers its own copy: one app's document changed leaves the others alone,
    and an app asking for a login still declares its security."""
    from polynav.api import ApiConfig, create_app

    plain = [create_app(fake_runtime, ApiConfig(port=0, auth=False)) for _ in range(2)]
    gated = create_app(fake_runtime, ApiConfig(port=0, auth=True))
    first, second = (app.openapi() for app in plain)
    assert first == second and first is not second
    first["paths"].clear()
    assert plain[1].openapi()["paths"] == second["paths"] != {}
    assert create_app(fake_runtime, ApiConfig(port=0, auth=False)).openapi()["paths"]
    assert "securitySchemes" not in second.get("components", {})
    assert "securitySchemes" in gated.openapi()["components"]
    assert set(gated.openapi()["paths"]) >= set(second["paths"])
