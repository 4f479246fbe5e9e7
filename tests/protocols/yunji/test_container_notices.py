"""Containers over a real TCP socket on the demo site (§D.8): a move to a container marker
(type 1001) docks to the cart standing there, the next move leaves it first; a container not
where its marker says fails; a leave held under the cart is retried and fails. Every code from
the runtime's cart service running in simulation."""

from __future__ import annotations

from typing import Any

from polynav.geometry import Pose2D
from tests.protocols.yunji.conftest import Client, Harness

CART = "cart_1"  # floor 1, (8.6, 2.0) facing east, 40 kg: near the robot's start

COVERED: dict[str, str] = {
    "notify 10 01060": "test_a_move_to_a_container_marker_docks_and_the_next_move_leaves_it",
    "notify 10 01061": "test_a_move_to_a_container_marker_docks_and_the_next_move_leaves_it",
    "notify 10 01050": "test_a_move_to_a_container_marker_docks_and_the_next_move_leaves_it",
    "notify 10 01051": "test_a_move_to_a_container_marker_docks_and_the_next_move_leaves_it",
    "notify 10 01062": "test_a_container_not_where_its_marker_is_fails_01062",
    "notify 10 01052": "test_a_leave_held_under_the_container_is_retried_then_fails",
    "notify 10 01053": "test_a_leave_held_under_the_container_is_retried_then_fails",
}


def _ok(client: Client, command: str) -> dict[str, Any]:
    reply = client.request(command)
    assert reply["status"] == "OK", reply
    return reply


def _marker(client: Client, name: str, pose: Pose2D, kind: int) -> None:
    _ok(client, f"/api/markers/insert_by_pose?name={name}&x={pose.x:.4f}&y={pose.y:.4f}"
                f"&theta={pose.theta:.5f}&type={kind}")


def _codes_until(h: Harness, client: Client, last: str, timeout: float = 120.0,
                 seen: list[str] | None = None) -> list[str]:
    """Notification codes up to ``last``, the runtime advanced and ``robot_status`` polled
    (notifications arrive on the way to its replies); the ``running_status`` values polled go
    into ``seen``."""
    out: list[str] = []
    waited = 0.0
    while waited < timeout:
        status = _ok(client, "/api/robot_status")["results"]["running_status"]
        if seen is not None:
            seen.append(status)
        while any(p["type"] == "notification" for p in client.pushed):
            code = client.push("notification")["code"]
            out.append(code)
            if code == last:
                return out
        h.runtime.advance(0.25)
        waited += 0.25
    raise AssertionError(f"no {last} within {timeout} s: {out}")


def test_a_move_to_a_container_marker_docks_and_the_next_move_leaves_it(
        harness: Harness, client: Client) -> None:
    cart = harness.runtime.simulation.world.cart(CART)
    _marker(client, "container_a", cart.pose, 1001)
    reply = _ok(client, "/api/move?marker=container_a")
    assert len(reply["task_id"]) == 32
    statuses: list[str] = []
    harness.runtime.advance(0.5)
    assert _ok(client, "/api/robot_status")["results"]["move_status"] == "running"
    codes = _codes_until(harness, client, "01061", seen=statuses)
    # The way to the container is a move of its own (01001 .. 01002) inside the dock.
    assert codes == ["01001", "01060", "01002", "01061"], codes
    assert "dock_to_container" in statuses
    assert harness.runtime.simulation.load is not None
    assert _ok(client, "/api/robot_status")["results"]["move_status"] == "succeeded"
    # Busy docking or not, the next move leaves the container first, then goes.
    _ok(client, "/api/move?marker=lobby")
    statuses.clear()
    codes = _codes_until(harness, client, "01002", seen=statuses)
    assert codes == ["01050", "01051", "01001", "01002"], codes
    assert "leave_container" in statuses
    sim = harness.runtime.simulation
    assert sim.load is None
    assert sim.scene.carts.carts[CART].pose.distance_to(cart.pose) < 0.1


def test_a_container_not_where_its_marker_is_fails_01062(
        harness: Harness, client: Client) -> None:
    sim = harness.runtime.simulation
    cart = sim.world.cart(CART)
    # Someone pushed the cart 0.8 m along the wall: no legs where the marker says.
    harness.runtime.run_between_ticks(lambda: setattr(
        sim.scene.carts.carts[CART], "pose", cart.pose.compose(Pose2D(0.0, 0.8, 0.0))))
    _marker(client, "container_a", cart.pose, 1001)
    _ok(client, "/api/move?marker=container_a")
    codes = _codes_until(harness, client, "01062")
    assert codes[:3] == ["01001", "01060", "01002"] and "01061" not in codes, codes
    assert _ok(client, "/api/robot_status")["results"]["move_status"] == "failed"
    assert sim.load is None


def test_a_leave_held_under_the_container_is_retried_then_fails(
        harness: Harness, client: Client) -> None:
    sim = harness.runtime.simulation
    _marker(client, "container_a", sim.world.cart(CART).pose, 1001)
    _ok(client, "/api/move?marker=container_a")
    _codes_until(harness, client, "01061")
    sim.press_estop()  # held: the robot cannot drive out from under the cart
    reply = client.request("/api/move?marker=lobby")
    assert reply["status"] == "OK", reply
    codes = _codes_until(harness, client, "01052")
    assert [c for c in codes if c != "02003"] == ["01050", "01053", "01053", "01052"], codes


def test_a_dock_is_the_move_task_and_is_cancelled_with_it(
        harness: Harness, client: Client) -> None:
    sim = harness.runtime.simulation
    _marker(client, "container_a", sim.world.cart(CART).pose, 1001)
    _ok(client, "/api/move?marker=container_a")
    harness.runtime.advance(1.0)
    _ok(client, "/api/move/cancel")
    codes = _codes_until(harness, client, "01062")
    assert codes == ["01001", "01060", "01004", "01062"], codes
    assert not harness.runtime.carts.busy and sim.load is None
    assert client.request("/api/move/cancel")["status"] == "REQUEST_DENIED"
