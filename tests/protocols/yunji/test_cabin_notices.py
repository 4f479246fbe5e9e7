"""Mobile cabins over a real TCP socket on the demo site (§D.8): a move to a cabin marker (type
1002) with another ``cabin_id`` is refused with 01028 then 01082; with its own id it docks
(01080, 01081); the next move leaves it first, a leave held once retried (01073) and one held
throughout failed (01072). Every code from the runtime's cart service in simulation."""

from __future__ import annotations

import dataclasses
from typing import Any

import pytest

from polynav.geometry import Pose2D
from polynav.worlds import load_world
from polynav.worlds.world import World
from tests.protocols.yunji.conftest import Client, Harness
from tests.protocols.yunji.test_container_notices import _codes_until

CABIN = "cabin_1"  # floor 2, housekeeping, (1.6, 4.3) facing west; its tag reads CAB-0001

COVERED: dict[str, str] = {
    "notify 10 01028": "test_a_cabin_with_another_id_is_refused_then_its_own_docks",
    "notify 10 01080": "test_a_cabin_with_another_id_is_refused_then_its_own_docks",
    "notify 10 01081": "test_a_cabin_with_another_id_is_refused_then_its_own_docks",
    "notify 10 01082": "test_a_cabin_with_another_id_is_refused_then_its_own_docks",
    "notify 10 01070": "test_leaving_a_cabin_is_retried_once_held_and_fails_held_throughout",
    "notify 10 01071": "test_leaving_a_cabin_is_retried_once_held_and_fails_held_throughout",
    "notify 10 01072": "test_leaving_a_cabin_is_retried_once_held_and_fails_held_throughout",
    "notify 10 01073": "test_leaving_a_cabin_is_retried_once_held_and_fails_held_throughout",
}


@pytest.fixture
def world() -> World:
    """The demo, the robot starting on floor 2 in the housekeeping room with the cabin."""
    demo = load_world("demo")
    start = demo.floor("floor2").point("housekeeping").pose
    return dataclasses.replace(demo, start_floor="floor2", start_pose=start)


def _ok(client: Client, command: str) -> dict[str, Any]:
    reply = client.request(command)
    assert reply["status"] == "OK", reply
    return reply


def _cabin_marker(client: Client, pose: Pose2D) -> None:
    _ok(client, f"/api/markers/insert_by_pose?name=cabin_a&x={pose.x:.4f}&y={pose.y:.4f}"
                f"&theta={pose.theta:.5f}&type=1002")


def _dock(harness: Harness, client: Client) -> None:
    _cabin_marker(client, harness.runtime.simulation.world.cart(CABIN).pose)
    _ok(client, "/api/move?marker=cabin_a&cabin_id=CAB-0001")
    assert _codes_until(harness, client, "01081")[-2:] == ["01002", "01081"]


def test_a_cabin_with_another_id_is_refused_then_its_own_docks(
        harness: Harness, client: Client) -> None:
    sim = harness.runtime.simulation
    _cabin_marker(client, sim.world.cart(CABIN).pose)
    _ok(client, "/api/move?marker=cabin_a&cabin_id=CAB-0042")
    statuses: list[str] = []
    codes = _codes_until(harness, client, "01082", seen=statuses)
    assert codes == ["01001", "01080", "01002", "01028", "01082"], codes
    assert "dock_to_cabin" in statuses
    assert sim.load is None
    assert sim.true_pose.distance_to(sim.world.cart(CABIN).pose) > 0.5  # backed out
    _ok(client, "/api/move?marker=cabin_a&cabin_id=CAB-0001")
    codes = _codes_until(harness, client, "01081")
    assert codes == ["01001", "01080", "01002", "01081"], codes
    load = sim.load
    assert load is not None and load.name == CABIN


def test_leaving_a_cabin_is_retried_once_held_and_fails_held_throughout(
        harness: Harness, client: Client) -> None:
    sim = harness.runtime.simulation
    _dock(harness, client)
    # Held throughout: every try to drive out stalls.
    sim.press_estop()
    _ok(client, "/api/move?marker=housekeeping")
    codes = [c for c in _codes_until(harness, client, "01072") if c != "02003"]
    assert codes == ["01070", "01073", "01073", "01072"], codes
    sim.release_estop()
    # The latch let go; it was the way out that stayed blocked: the robot stands in the
    # cabin carrying nothing, and the next move is a plain one.
    assert sim.load is None
    # Dock again; this time held for one try only.
    harness.runtime.advance(1.0)
    _ok(client, "/api/move?marker=lounge")  # out of the cabin first
    _codes_until(harness, client, "01002")
    _dock(harness, client)
    sim.press_estop()
    _ok(client, "/api/move?marker=housekeeping")
    codes = [c for c in _codes_until(harness, client, "01073") if c != "02003"]
    assert codes == ["01070", "01073"], codes
    sim.release_estop()
    codes = [c for c in _codes_until(harness, client, "01002") if c != "02004"]
    assert codes == ["01071", "01001", "01002"], codes
    assert sim.load is None
