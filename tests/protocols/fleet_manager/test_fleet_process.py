"""``polynav fleet`` over HTTP and WebSocket, dispatching missions to the robots of a
``Building`` on the same real broker (``--no-fleet-manager``: vehicles only), both paced at
the same speed."""

from __future__ import annotations

import json
import socket
import time
from collections.abc import Iterator
from contextlib import contextmanager
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
from tests.helpers.waiting import wait_for
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


def mission(client: httpx.Client, mission_id: str) -> dict[str, Any]:
    got: dict[str, Any] = client.get(f"/api/missions/{mission_id}").json()
    return got


def mission_end(client: httpx.Client, mission_id: str, timeout: float) -> dict[str, Any]:
    """Mission ``mission_id`` once done or failed."""
    ended: dict[str, Any] = wait_for(
        lambda: (got := mission(client, mission_id))["state"] in ("done", "failed") and got,
        timeout, f"mission {mission_id} to end")
    return ended


@contextmanager
def fleet_over_both_robots(broker: Mosquitto, building: Building, store: SiteStore,
                           tmp_path: Path, start_fleet: list[FleetProcess]
                           ) -> Iterator[httpx.Client]:
    """A client of a started ``polynav fleet`` once it knows both robots' states; the process
    must then exit 0 when stopped."""
    fleet = FleetProcess(fleet_args(broker, store, tmp_path))
    start_fleet.append(fleet)
    assert fleet.url, fleet.lines
    building.start()
    with httpx.Client(base_url=fleet.url, timeout=10.0) as client:
        wait_for(lambda: len([r for r in client.get("/api/robots").json()
                              if r["map"] is not None]) == 2, 15.0, "both robots' states")
        yield client
    status, err = fleet.stop()
    assert status == 0, err


def test_a_mission_posted_over_http_is_dispatched_to_the_nearest_robot_and_done(
        broker: Mosquitto, building: Building, store: SiteStore, tmp_path: Path,
        start_fleet: list[FleetProcess]) -> None:
    with fleet_over_both_robots(broker, building, store, tmp_path, start_fleet) as client, \
            ws_connect(str(client.base_url).replace("http", "ws") + "/api/ws") as ws:
        posted = client.post("/api/missions", json={
            "stops": [{"point": "front_desk", "map": "floor1"}], "mission_id": "desk"})
        assert posted.status_code == 202
        assert posted.json() == {"mission_id": "desk", "state": "queued"}
        done = mission_end(client, "desk", 40.0)
        assert (done["state"], done["robot"], done["attempts"]) == ("done", "robot2", 1)
        # robot2 stood nearer
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


def test_a_mission_to_another_floor_goes_through_a_lift_with_its_lease_recorded(
        broker: Mosquitto, building: Building, store: SiteStore, tmp_path: Path,
        start_fleet: list[FleetProcess]) -> None:
    with fleet_over_both_robots(broker, building, store, tmp_path, start_fleet) as client:
        posted = client.post("/api/missions", json={"stops": [
            {"point": "corridor_east", "map": "floor2"}]})
        assert posted.status_code == 202
        done = mission_end(client, posted.json()["mission_id"], 120.0)
        assert (done["state"], done["robot"]) == ("done", "robot1")
        robot = client.get("/api/robots/robot1").json()
        assert robot["map"] == "floor2"
        leases = [e for e in client.get("/api/audit").json()
                  if e["what"] == "lease.granted" and e["detail"]["resource"].startswith(
                      "lift:")]
        assert leases and leases[0]["detail"]["holder"] == "robot1"


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
    with fleet_over_both_robots(broker, building, store, tmp_path, start_fleet) as client:
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
        done = mission_end(client, "m", 60.0)
        assert (done["state"], done["robot"], done["attempts"]) == ("done", "robot2", 2)
        audit = client.get("/api/audit").json()
        assert [e["detail"]["robot"] for e in audit if e["what"] == "mission.requeued"] == [
            "robot1"]
        assert {"robot": "robot1", "state": "CONNECTIONBROKEN"} in [
            e["detail"] for e in audit if e["what"] == "robot.connection"]
