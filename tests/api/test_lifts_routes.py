"""GET /api/lifts, an operator's request to a car, its mode; a goal naming an unknown map."""

from __future__ import annotations

import httpx

from tests.api.fakes import FakeRuntime


def test_lists_both_cars_with_their_floors(client: httpx.Client) -> None:
    body = client.get("/api/lifts").json()
    cars = {car["name"]: car for car in body["lifts"]}
    assert sorted(cars) == ["lift_1", "lift_2"]
    assert cars["lift_1"]["floors"] == ["floor1", "floor2", "floor3"]
    assert cars["lift_2"]["floors"] == ["floor1", "floor2"]
    assert cars["lift_1"] | {"floors": None} == {
        "name": "lift_1", "floors": None, "current_floor": "floor1",
        "destination_floor": "floor1", "door": "closed", "motion": "stopped", "mode": "normal",
        "session": "", "riders": 0, "capacity": 2}


def test_operator_request_takes_the_session_and_moves_the_car(
    client: httpx.Client, fake_runtime: FakeRuntime
) -> None:
    answer = client.post("/api/lifts/lift_1/request", json={"floor": "floor3"})
    assert answer.status_code == 200 and answer.json()["session"] == "operator"
    fake_runtime.advance(12.0)
    car = client.get("/api/lifts").json()["lifts"][0]
    assert (car["current_floor"], car["door"]) == ("floor3", "open")
    busy = client.post("/api/lifts/lift_1/request", json={"floor": "floor1", "session": "bob"})
    assert busy.status_code == 409 and "operator" in busy.json()["error"]["message"]
    ended = client.post("/api/lifts/lift_1/request", json={"end_session": True})
    assert ended.json()["session"] == ""


def test_bad_lift_requests_get_clear_errors(client: httpx.Client) -> None:
    unserved = client.post("/api/lifts/lift_2/request", json={"floor": "floor3"})
    assert unserved.status_code == 409
    assert "does not serve floor 'floor3'" in unserved.json()["error"]["message"]
    assert client.post("/api/lifts/lift_9/request", json={"floor": "floor1"}).status_code == 404
    assert client.post("/api/lifts/lift_1/request", json={}).status_code == 409
    assert client.post("/api/lifts/lift_1/request", json={"floor": 3}).status_code == 422
    assert client.post("/api/lifts/lift_1/mode", json={"mode": "broken"}).status_code == 422


def test_out_of_service_car_refuses_requests(client: httpx.Client) -> None:
    assert client.post("/api/lifts/lift_1/mode", json={"mode": "out_of_service"}).status_code \
        == 200
    refused = client.post("/api/lifts/lift_1/request", json={"floor": "floor2"})
    assert refused.status_code == 409 and "out of service" in refused.json()["error"]["message"]
    assert client.get("/api/lifts").json()["lifts"][0]["mode"] == "out_of_service"


def test_goal_on_an_unknown_map_is_404(client: httpx.Client) -> None:
    client.post("/api/navigation/start", json={"map": "floor1"})
    answer = client.post("/api/navigation/goal", json={"point": "room_301", "map": "roof"})
    assert answer.status_code == 404 and "roof" in answer.json()["error"]["message"]
