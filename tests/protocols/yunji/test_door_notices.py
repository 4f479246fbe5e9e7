"""Electronic doors and gates on a move, over the real socket (§3.10.4, "passing a gate or
electronic door"): the lobby gate of floor 1 lies between the robot's start and the main
corridor. Passing it sends 01030 then 01031 (with the move's target); a robot that holds it too
long (stopped by the software e-stop while it controls the gate) has it released by force
(01032), and a move that still has to pass it then fails (01003)."""

from __future__ import annotations

from typing import Any

from polynav.robot.lift import DoorState
from tests.protocols.yunji.conftest import Client, Harness

GATE = "lobby_gate"


def _ok(client: Client, command: str) -> dict[str, Any]:
    reply = client.request(command)
    assert reply["status"] == "OK", reply
    return reply


def _run_until_ended(h: Harness, client: Client, timeout: float = 200.0) -> str:
    for _ in range(int(timeout / 0.5)):
        h.runtime.advance(0.5)
        status = _ok(client, "/api/robot_status")["results"]
        if status["move_status"] != "running":
            return str(status["move_status"])
    raise AssertionError("the move never ended")


def _notices(client: Client) -> list[tuple[str, dict[str, Any]]]:
    """Notifications up to the move's end (01002/01003)."""
    out = []
    while True:
        packet = client.push("notification")
        out.append((packet["code"], packet["data"]))
        if packet["code"] in ("01002", "01003"):
            return out


def test_passing_the_lobby_gate_sends_01030_then_01031(harness: Harness,
                                                       client: Client) -> None:
    _ok(client, "/api/move?marker=corridor_west")
    assert _run_until_ended(harness, client) == "succeeded"
    notices = [(code, data) for code, data in _notices(client)
               if code in ("01001", "01030", "01031", "01032", "01002")]
    assert notices == [
        ("01001", {"target": "corridor_west"}),
        ("01030", {"target": "corridor_west"}),
        ("01031", {"target": "corridor_west"}),
        ("01002", notices[-1][1]),
    ]
    harness.runtime.advance(3.0)
    assert harness.runtime.door(GATE).state().state is DoorState.CLOSED
    assert harness.runtime.simulation.collisions == []


def test_a_gate_held_too_long_is_released_by_force_with_01032(harness: Harness,
                                                              client: Client) -> None:
    runtime = harness.runtime
    _ok(client, "/api/move?marker=corridor_west")
    for _ in range(200):  # until the robot controls the gate
        runtime.advance(0.1)
        if runtime.doors_rule.held == (GATE,):
            break
    assert runtime.doors_rule.held == (GATE,)
    _ok(client, "/api/estop?flag=true")  # stopped before the gate while holding it
    runtime.advance(runtime.doors_rule.config.max_control + 2.0)
    assert runtime.doors_rule.held == ()
    assert runtime.robot_id not in runtime.door(GATE).state().holders
    _ok(client, "/api/estop?flag=false")
    assert _run_until_ended(harness, client) == "failed"
    codes = [code for code, _ in _notices(client)]
    assert [c for c in codes if c in ("01001", "01030", "01031", "01032", "01003")] == [
        "01001", "01030", "01032", "01003"]
    status = runtime.status()
    assert status.reason is not None and GATE in status.reason and "by force" in status.reason
    assert runtime.simulation.collisions == []


COVERED: dict[str, str] = {
    "notify 10 01030": "test_passing_the_lobby_gate_sends_01030_then_01031",
    "notify 10 01031": "test_passing_the_lobby_gate_sends_01030_then_01031",
    "notify 10 01032": "test_a_gate_held_too_long_is_released_by_force_with_01032",
}
