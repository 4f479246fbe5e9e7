"""``polynav run --broker``: a lone robot, and a building's robots and master, as VDA 5050
clients of a real Mosquitto; only the transport differs from the in-process building."""

from __future__ import annotations

import subprocess
import time
from pathlib import Path

import orjson
import pytest

from polynav.fleet.vda5050 import validation
from polynav.fleet.vehicle import VehicleConfig
from polynav.house.building import Building
from polynav.runtime.config import RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.helpers.mosquitto import Mosquitto, mosquitto_binary
from tests.helpers.polynav_run import start_run, startup_lines, stop_run


def retained(broker: Mosquitto, topic: str) -> dict[str, object]:
    got = subprocess.run(
        [mosquitto_binary("mosquitto_sub"), "-h", "127.0.0.1", "-p", str(broker.port),
         "-t", topic, "-C", "1", "-W", "10"],
        capture_output=True, text=True, timeout=15.0, check=True)
    body: dict[str, object] = orjson.loads(got.stdout)
    return body


def test_polynav_run_with_a_broker_is_a_vehicle_online_then_offline(
        broker: Mosquitto, tmp_path: Path) -> None:
    proc = start_run(tmp_path, None, "--broker", broker.url, "--vda-version", "2.1.0",
                     "--vda-manufacturer", "acme", "--vda-serial", "agv7")
    lines = startup_lines(proc)
    assert any("VDA 5050 2.1.0 vehicle on " + broker.url in line for line in lines), lines
    base = "uagv/v2/acme/agv7"
    online = retained(broker, f"{base}/connection")
    validation.validate("connection", "2.1.0", online)
    assert (online["connectionState"], online["manufacturer"], online["serialNumber"]) == (
        "ONLINE", "acme", "agv7")
    sheet = retained(broker, f"{base}/factsheet")
    validation.validate("factsheet", "2.1.0", sheet)
    stop_run(proc, lines)
    offline = retained(broker, f"{base}/connection")
    assert offline["connectionState"] == "OFFLINE"
    assert isinstance(offline["headerId"], int) and isinstance(online["headerId"], int)
    assert offline["headerId"] > online["headerId"]


def test_polynav_run_with_an_unreachable_broker_says_so_and_exits(tmp_path: Path) -> None:
    proc = start_run(tmp_path, None, "--broker", "mqtt://127.0.0.1:1", "--vda-serial", "r",
                     "--connect-timeout", "1")
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 1
    assert "mqtt://127.0.0.1:1 not reachable after 1.0 s" in err


@pytest.mark.parametrize(("robots", "timeout"), [((), "0"), (("--robots", "2"), "nan")],
                         ids=["lone", "building"])
def test_a_connect_timeout_not_above_zero_is_refused_by_name(
        tmp_path: Path, robots: tuple[str, ...], timeout: str) -> None:
    proc = start_run(tmp_path, None, *robots, "--broker", "mqtt://127.0.0.1:1",
                     "--connect-timeout", timeout)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode in (1, 2), err
    assert "connect_timeout" in err and "> 0" in err, err
    assert "Traceback" not in err


def test_a_building_over_the_broker_runs_orders_as_in_process(
        broker: Mosquitto, world: World, store: SiteStore) -> None:
    building = Building(store, world, robots=2, config=RuntimeConfig(people=False),
                        vehicles=VehicleConfig(broker.url, version="2.1.0",
                                               visualization_period=None))
    try:
        assert all(building.master.state(s) is not None for s in building.serials)
        first = building.send("robot1", "lobby", "floor1")
        second = building.send("robot2", "office_1", "floor1")

        def done() -> bool:
            time.sleep(0.002)  # wall time for the broker between control periods
            return None not in (building.outcome("robot1", first),
                                building.outcome("robot2", second))

        assert building.advance_until(done, timeout=150.0)
        assert (building.outcome("robot1", first), building.outcome("robot2", second)) == (
            "succeeded", "succeeded")
        entries = {e.robot_id: e for e in building.entries()}
        assert entries["robot1"].order_state == "succeeded"
    finally:
        building.close()
    assert retained(broker, "uagv/v2/polynav/robot2/connection")["connectionState"] == "OFFLINE"


def test_a_vehicle_killed_leaves_its_will_connectionbroken(
        broker: Mosquitto, tmp_path: Path) -> None:
    proc = start_run(tmp_path, None, "--broker", broker.url, "--vda-serial", "agv9")
    lines = startup_lines(proc)
    assert any("vehicle on" in line for line in lines), lines
    assert retained(broker, "uagv/v2/polynav/agv9/connection")["connectionState"] == "ONLINE"
    proc.kill()  # no OFFLINE, no clean DISCONNECT: the broker publishes the will
    proc.communicate(timeout=30)
    deadline = time.monotonic() + 10.0
    state = None
    while time.monotonic() < deadline:
        will = retained(broker, "uagv/v2/polynav/agv9/connection")
        validation.validate("connection", "2.0.0", will)
        state = will["connectionState"]
        if state == "CONNECTIONBROKEN":
            break
        time.sleep(0.1)
    assert state == "CONNECTIONBROKEN"
