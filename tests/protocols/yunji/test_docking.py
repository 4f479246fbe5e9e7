"""Docking by what the robot sees, over a real TCP socket on the demo site: a charger marker
off the real charger still docks, and each part of the charger that fails is told by its own
code (01023 data link, 01024 no plate, 01025 no current, 01026 no beacon).

The charger's faults are the simulator's (``Simulation.inject_fault``): the plate, beacon, link
and mains of the simulated charger break as a real one's do.
"""

from __future__ import annotations

import math
from typing import Any

import pytest

from polynav.geometry import Pose2D, angle_diff
from tests.protocols.yunji.conftest import Client, Harness

TIMEOUT = 300.0  # simulated seconds
CHARGER = Pose2D(0.8, 14.0, math.pi)  # the demo's charger, where a docked robot stands


def _ok(client: Client, command: str) -> dict[str, Any]:
    reply = client.request(command)
    assert reply["status"] == "OK", reply
    return reply


def _move(h: Harness, client: Client, marker: str) -> dict[str, Any]:
    """Move to ``marker`` and advance until the move ends; the last robot_status."""
    _ok(client, f"/api/move?marker={marker}")
    for _ in range(int(TIMEOUT / 0.5)):
        h.runtime.advance(0.5)
        status = _ok(client, "/api/robot_status")["results"]
        if status["move_status"] != "running":
            h.runtime.advance(0.5)
            return dict(_ok(client, "/api/robot_status")["results"])
    raise AssertionError("the move did not end")


def _codes_until(client: Client, last: str) -> list[tuple[str, dict[str, Any]]]:
    out = []
    while True:
        packet = client.push("notification")
        out.append((packet["code"], packet["data"]))
        if packet["code"] == last:
            return out


def _marker_off(name: str) -> str:
    """A charger marker 10 cm and 5 degrees off the charger: 6 cm short of it, 8 cm to its
    left, turned 5 degrees."""
    pose = CHARGER.compose(Pose2D(-0.06, 0.08, math.radians(5.0)))
    return (f"/api/markers/insert_by_pose?name={name}&x={pose.x:.4f}&y={pose.y:.4f}"
            f"&theta={pose.theta:.5f}&type=11")


def test_a_marker_10_cm_and_5_degrees_off_the_charger_still_docks(
    harness: Harness, client: Client
) -> None:
    _ok(client, _marker_off("moved_pile"))
    status = _move(harness, client, "moved_pile")
    assert (status["move_status"], status["charge_state"]) == ("succeeded", True)
    codes = [c for c, _ in _codes_until(client, "02001")]
    assert codes == ["01001", "01020", "01021", "01002", "02001"]
    truth = harness.runtime.simulation.true_pose
    assert truth.distance_to(CHARGER) < 0.02
    assert abs(angle_diff(truth.theta, CHARGER.theta)) < math.radians(1.5)


@pytest.mark.parametrize(("fault", "code"), [
    ("charger_beacon_off", "01026"),
    ("charger_link_invalid", "01023"),
    ("charger_no_power", "01025"),
])
def test_a_broken_charger_fails_the_dock_with_its_code(
    harness: Harness, client: Client, fault: str, code: str
) -> None:
    harness.runtime.simulation.inject_fault(fault)
    status = _move(harness, client, "charger")
    assert (status["move_status"], status["charge_state"]) == ("failed", False)
    notes = _codes_until(client, "01003")
    assert [c for c, _ in notes] == ["01001", "01020", "01022", code, "01003"]
    assert notes[3] == (code, {"target": "charger"})


COVERED: dict[str, str] = {
    "notify 10 01023": "test_a_broken_charger_fails_the_dock_with_its_code",
    "notify 10 01025": "test_a_broken_charger_fails_the_dock_with_its_code",
    "notify 10 01026": "test_a_broken_charger_fails_the_dock_with_its_code",
}
