"""``polynav fleet`` over HTTP and WebSocket, dispatching missions to the robots of a
``Building`` on the same real broker (``--no-fleet-manager``: vehicles only), both paced at
the same speed."""

from __future__ import annotations

import json
import socket
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from websockets.sync.client import connect as ws_connect

from polynav.fleet.vehicle import VehicleConfig
from polynav.house.building import Building
from polynav.runtime.config import RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.helpers.mosquitto import Mosquitto
from tests.protocols.fleet_manager.conftest import FleetProcess

SPEED = 4.0


def fleet_args(broker: Mosquitto, store: SiteStore, tmp_path: Path, *extra: str) -> list[str]:
    return ["--broker", broker.url, "--data", str(store.data_dir), "--port", "0",
            "--speed", str(SPEED), "--db", f"sqlite:///{tmp_path / 'fleet.db'}",
            "--connect-timeout", "5", *extra]


@pytest.fixture
def building(broker: Mosquitto, world: World, store: SiteStore) -> Iterator[Building]:
    """Two robots on floor1 (one by lift 1, one at the initial point), vehicles only."""
    starts = [store.point("floor1", "corridor_east"), store.point("floor1", "initial")]
    built = Building(store, world, robots=2, starts=starts,
                     config=RuntimeConfig(people=False, speed=SPEED),
                     vehicles=VehicleConfig(broker.url, visualization_period=None),
                     fleet_manager=False)
    try:
        yield built
    finally:
        built.close()


def wait_for(check: Callable[[], Any], timeout: float, what: str) -> Any:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        got = check()
        if got:
            return got
        time.sleep(0.1)
    pytest.fail(f"timed out waiting for {what}")


def mission(client: httpx.Client, mission_id: str) -> dict[str, Any]:
    got: dict[str, Any] = client.get(f"/api/missions/{mission_id}").json()
    return got


def test_a_mission_posted_over_http_is_dispatched_to_the_nearest_robot_and_done(
        broker: Mosquitto, building: Building, store: SiteStore, tmp_path: Path,
        start_fleet: list[FleetProcess]) -> None:
    fleet = FleetProcess(fleet_args(broker, store, tmp_path))
    start_fleet.append(fleet)
    assert fleet.url, fleet.lines
    building.start()
    with httpx.Client(base_url=fleet.url, timeout=10.0) as client, \
            ws_connect(fleet.url.replace("http", "ws") + "/api/ws") as ws:
        wait_for(lambda: len([r for r in client.get("/api/robots").json()
                              if r["map"] is not None]) == 2, 15.0, "both robots' states")
        posted = client.post("/api/missions", json={
            "stops": [{"point": "front_desk", "map": "floor1"}], "mission_id": "desk"})
        assert posted.status_code == 202
        assert posted.json() == {"mission_id": "desk", "state": "queued"}
        done = wait_for(lambda: (got := mission(client, "desk"))["state"] == "done" and got,
                        40.0, "the mission to be done")
        assert (done["robot"], done["attempts"]) == ("robot2", 1)  # robot2 stood nearer
        kinds = []
        deadline = time.monotonic() + 5.0
        while "mission.done" not in kinds and time.monotonic() < deadline:
            message = json.loads(ws.recv(timeout=5.0))
            if message["type"] == "event":
                kinds.append(message["kind"])
            else:
                assert message["type"] == "robots"
        assert kinds[-4:] == ["mission.queued", "mission.dispatched", "mission.started",
                              "mission.done"]
        audit = [e["what"] for e in client.get("/api/audit").json()]
        assert {"mission.added", "mission.claimed", "order.sent", "order.confirmed",
                "mission.done"} <= set(audit)
    status, err = fleet.stop()
    assert status == 0, err


def test_a_mission_to_another_floor_goes_through_a_lift_with_its_lease_recorded(
        broker: Mosquitto, building: Building, store: SiteStore, tmp_path: Path,
        start_fleet: list[FleetProcess]) -> None:
    fleet = FleetProcess(fleet_args(broker, store, tmp_path))
    start_fleet.append(fleet)
    assert fleet.url, fleet.lines
    building.start()
    with httpx.Client(base_url=fleet.url, timeout=10.0) as client:
        wait_for(lambda: len([r for r in client.get("/api/robots").json()
                              if r["map"] is not None]) == 2, 15.0, "both robots' states")
        posted = client.post("/api/missions", json={"stops": [
            {"point": "corridor_east", "map": "floor2"}]})
        assert posted.status_code == 202
        mission_id = posted.json()["mission_id"]
        done = wait_for(lambda: (got := mission(client, mission_id))["state"] in (
            "done", "failed") and got, 120.0, "the mission to end")
        assert (done["state"], done["robot"]) == ("done", "robot1")
        robot = client.get("/api/robots/robot1").json()
        assert robot["map"] == "floor2"
        leases = [e for e in client.get("/api/audit").json()
                  if e["what"] == "lease.granted" and e["detail"]["resource"].startswith(
                      "lift:")]
        assert leases and leases[0]["detail"]["holder"] == "robot1"
    status, err = fleet.stop()
    assert status == 0, err


def test_an_unreachable_broker_or_database_is_one_line_and_exit_1(
        tmp_path: Path, broker: Mosquitto, store: SiteStore) -> None:
    no_broker = FleetProcess(["--broker", "mqtt://127.0.0.1:1", "--data", str(tmp_path / "d"),
                              "--port", "0", "--connect-timeout", "1"])
    status, err = no_broker.stop()
    assert status == 1
    assert err.strip().splitlines()[-1].startswith("polynav fleet: MQTT broker at "
                                                   "mqtt://127.0.0.1:1 not reachable")
    no_db = FleetProcess(["--broker", broker.url, "--data", str(tmp_path / "d"), "--port", "0",
                          "--db", "postgresql://nobody@127.0.0.1:1/fleet",
                          "--connect-timeout", "1"])
    status, err = no_db.stop()
    assert status == 1
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "unreachable" in lines[0], err


def _sever(building: Building, serial: str) -> None:
    """Kill robot ``serial``'s MQTT client as a crash would: its network loop ends and its TCP
    connection drops without DISCONNECT or OFFLINE, so the broker publishes its last will."""
    (link,) = [link for link in building.links if link.serial_number == serial]
    client = link.transport._client  # noqa: SLF001 (no public way to crash a client)
    client.loop_stop()
    sock = client.socket()
    assert sock is not None
    sock.shutdown(socket.SHUT_RDWR)


def test_a_robot_killed_mid_mission_loses_its_leases_and_another_robot_finishes_it(
        broker: Mosquitto, building: Building, store: SiteStore, tmp_path: Path,
        start_fleet: list[FleetProcess]) -> None:
    fleet = FleetProcess(fleet_args(broker, store, tmp_path))
    start_fleet.append(fleet)
    assert fleet.url, fleet.lines
    building.start()
    with httpx.Client(base_url=fleet.url, timeout=10.0) as client:
        wait_for(lambda: len([r for r in client.get("/api/robots").json()
                              if r["map"] is not None]) == 2, 15.0, "both robots' states")
        posted = client.post("/api/missions", json={"stops": [
            {"point": "office_4", "map": "floor1"}], "mission_id": "m"})
        assert posted.status_code == 202
        wait_for(lambda: any(e["what"] == "order.confirmed"
                             for e in client.get("/api/audit").json()),
                 20.0, "the robot to take the order")
        assert mission(client, "m")["robot"] == "robot1"
        _sever(building, "robot1")
        wait_for(lambda: client.get("/api/robots/robot1").json()["connection"]
                 == "CONNECTIONBROKEN", 20.0, "robot1's last will")
        building.runtimes[0].cancel()  # the dead robot stops where it is
        assert all(lease["holder"] != "robot1" for lease in client.get("/api/leases").json())
        done = wait_for(lambda: (got := mission(client, "m"))["state"] in ("done", "failed")
                        and got, 60.0, "the mission to end")
        assert (done["state"], done["robot"], done["attempts"]) == ("done", "robot2", 2)
        audit = client.get("/api/audit").json()
        assert [e["detail"]["robot"] for e in audit if e["what"] == "mission.requeued"] == [
            "robot1"]
        assert {"robot": "robot1", "state": "CONNECTIONBROKEN"} in [
            e["detail"] for e in audit if e["what"] == "robot.connection"]
    status, err = fleet.stop()
    assert status == 0, err
