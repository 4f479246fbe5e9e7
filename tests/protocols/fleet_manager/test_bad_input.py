"""Bad input to ``polynav fleet``: requests its API refuses with a clear 4xx in the one error
shape, and malformed or schema-breaking messages on every topic it subscribes to (connection,
state, zone requests), which are logged and never stop it."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import httpx
import pytest

from polynav.fleet import messages as m
from polynav.fleet.mqtt_transport import MqttTransport
from polynav.store.site_store import SiteStore
from tests.helpers.mosquitto import Mosquitto
from tests.helpers.scripted_vehicle import Robot
from tests.helpers.waiting import wait_for
from tests.protocols.fleet_manager.conftest import FleetProcess


@pytest.fixture
def fleet(broker: Mosquitto, store: SiteStore, tmp_path: Path,
          start_fleet: list[FleetProcess]) -> FleetProcess:
    process = FleetProcess(["--broker", broker.url, "--data", str(store.data_dir),
                            "--port", "0", "--db", f"sqlite:///{tmp_path / 'fleet.db'}",
                            "--connect-timeout", "5", "--speed", "5"])
    start_fleet.append(process)
    assert process.url, process.lines
    return process


def error(response: httpx.Response) -> tuple[int, str]:
    body: dict[str, Any] = response.json()
    assert set(body) == {"error"} and set(body["error"]) == {"code", "message"}, body
    return response.status_code, body["error"]["code"]


BAD_MISSIONS: list[tuple[dict[str, Any], int, str, str]] = [
    ({"stops": [{"point": "nowhere", "map": "floor1"}]}, 404, "not_found", "floor1/nowhere"),
    ({"stops": [{"point": "lobby", "map": "floor9"}]}, 404, "not_found", "floor9"),
    ({"stops": []}, 422, "validation_error", "stops"),
    ({"stops": "lobby"}, 422, "validation_error", "stops"),
    ({"stops": [{"point": 5, "map": "floor1"}]}, 422, "validation_error", "point"),
    ({"stops": [{"point": "lobby"}]}, 422, "validation_error", "map"),
    ({"stops": [{"point": "lobby", "map": "floor1", "speed": 3}]}, 422, "validation_error",
     "speed"),
    ({"stops": [{"point": "lobby", "map": "floor1"}], "mission_id": "a/b"}, 422,
     "validation_error", "mission_id"),
]


def test_a_bad_mission_is_refused_with_a_clear_4xx_naming_what_is_wrong(
        fleet: FleetProcess) -> None:
    with httpx.Client(base_url=fleet.url, timeout=10.0) as client:
        for body, status, code, names in BAD_MISSIONS:
            response = client.post("/api/missions", json=body)
            assert error(response) == (status, code), body
            assert names in response.json()["error"]["message"], body
        assert client.get("/api/missions").json() == []


def test_bad_requests_of_every_route_get_their_4xx_and_the_manager_goes_on(
        fleet: FleetProcess) -> None:
    with httpx.Client(base_url=fleet.url, timeout=10.0) as client:
        malformed = client.post("/api/missions", content=b"{not json",
                                headers={"content-type": "application/json"})
        assert error(malformed) == (400, "malformed_json")
        assert error(client.get("/api/robots/robot9")) == (404, "not_found")
        assert error(client.get("/api/missions/nope")) == (404, "not_found")
        assert error(client.delete("/api/missions/nope")) == (404, "not_found")
        assert error(client.get("/api/missions", params={"state": "lost"})) == (
            422, "validation_error")
        assert error(client.get("/api/audit", params={"after": -1})) == (
            422, "validation_error")
        assert error(client.put("/api/missions")) == (405, "method_not_allowed")
        ok = client.post("/api/missions", json={
            "stops": [{"point": "lobby", "map": "floor1"}], "mission_id": "m1"})
        assert ok.status_code == 202
        again = client.post("/api/missions", json={
            "stops": [{"point": "lobby", "map": "floor1"}], "mission_id": "m1"})
        assert again.status_code == 202  # a retried request: the same mission
        other = client.post("/api/missions", json={
            "stops": [{"point": "kitchen", "map": "floor1"}], "mission_id": "m1"})
        assert error(other) == (409, "conflict")
        assert client.delete("/api/missions/m1").json()["state"] == "cancelled"
        assert client.delete("/api/missions/m1").json()["state"] == "cancelled"
        assert [m["mission_id"] for m in client.get(
            "/api/missions", params={"state": "cancelled"}).json()] == ["m1"]
        schema = client.get("/openapi.json").json()
        assert {"post_mission", "list_robots", "get_robot", "cancel_mission", "list_leases",
                "list_audit"} <= {op["operationId"] for path in schema["paths"].values()
                                  for op in path.values()}
    status, err = fleet.stop()
    assert status == 0, err


def test_malformed_messages_on_its_topics_are_logged_never_fatal(
        broker: Mosquitto, fleet: FleetProcess) -> None:
    base = "uagv/v2/polynav/intruder"
    peer = MqttTransport(broker.url, "test-peer")
    try:
        robot = Robot(peer, "intruder")
        assert peer.wait_subscribed(10.0)
        robot.connection(m.ConnectionState.ONLINE)  # known: its state and zones are heard
        with httpx.Client(base_url=fleet.url, timeout=10.0) as client:
            wait_for(lambda: client.get("/api/robots").json() != [], 10.0, "the robot")
            for kind in ("connection", "state", "zoneRequest"):
                peer.publish_raw(f"{base}/{kind}", b"{not json", retain=False)
                peer.publish_raw(f"{base}/{kind}", b'{"headerId": "one"}', retain=False)
                peer.publish_raw(f"{base}/{kind}", b"[1, 2, 3]", retain=False)
            peer.publish_raw("uagv/v2/polynav/other/connection", (  # a serial of no topic
                b'{"headerId": 1, "timestamp": "2026-11-28T11:40:03.120Z", "version": "2.0.0",'
                b' "manufacturer": "polynav", "serialNumber": "a/b",'
                b' "connectionState": "ONLINE"}'), retain=False)
            robot.state(battery=55.0)  # after the bad ones: once it is read, so were they
            got = wait_for(lambda: (r := client.get("/api/robots/intruder").json())[
                "state_at"] is not None and r, 10.0, "the robot's good state")
            assert (got["connection"], got["battery_percent"]) == ("ONLINE", 55.0)
            assert [r["serial"] for r in client.get("/api/robots").json()] == ["intruder"]
            assert client.post("/api/missions", json={
                "stops": [{"point": "lobby", "map": "floor1"}]}).status_code == 202
    finally:
        peer.close()
    status, err = fleet.stop()
    assert status == 0, err
    for kind in ("connection", "state", "zoneRequest"):
        assert f"refused a message on {base}/{kind}" in err, err
    assert "connection message not used: serial_number: 'a/b'" in err, err

