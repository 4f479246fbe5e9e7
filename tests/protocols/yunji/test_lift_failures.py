"""Lift rides that do not go to plan, over the real socket: the car held by someone else
(04070/04071), full (04033), not coming (04013), not arriving (04023), the car or its door
blocked (04032, 04002), the way out blocked (04052, 04060, 04061). Floor 3 is served by lift_1
only, so a car given up ends the move (01003) with the reason."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from polynav.robot.lift import LiftMode, LiftRequest
from polynav.robot.sim.lift_car import SimLiftCar
from polynav.runtime.route_run import MAX_DOOR_RETRIES, MAX_REQUEUES
from tests.protocols.yunji.conftest import Client, Harness

TIMEOUT = 600.0  # simulated seconds


def _ok(client: Client, command: str) -> dict[str, Any]:
    reply = client.request(command)
    assert reply["status"] == "OK", reply
    return reply


def _car(h: Harness) -> SimLiftCar:
    return h.runtime.simulation.scene.lifts["lift_1"]


def _run_until(h: Harness, client: Client, running_status: str | None,
               timeout: float = TIMEOUT) -> dict[str, Any]:
    """Advance until ``running_status`` shows (None: until the move ends); the status then."""
    for _ in range(int(timeout / 0.5)):
        h.runtime.advance(0.5)
        status = _ok(client, "/api/robot_status")["results"]
        if running_status is None and status["move_status"] != "running":
            return status
        if running_status is not None and status["running_status"] == running_status:
            return status
    raise AssertionError(f"never {running_status or 'ended'}")


def _lift_codes(client: Client) -> list[str]:
    codes = []
    while True:
        packet = client.push("notification")
        codes.append(packet["code"])
        if packet["code"] in ("01002", "01003"):
            return [c for c in codes if c.startswith("040") or c in ("01001", "01002", "01003")]


def test_car_held_by_an_operator_waits_for_the_unlock(harness: Harness, client: Client) -> None:
    harness.runtime.request_lift("lift_1", LiftRequest("operator", "floor2"))
    _ok(client, "/api/move?marker=room_301")
    _run_until(harness, client, "wait_lift_unlock")
    harness.runtime.advance(20.0)
    assert _ok(client, "/api/robot_status")["results"]["running_status"] == "wait_lift_unlock"
    harness.runtime.request_lift("lift_1", LiftRequest("operator", end_session=True))
    assert _run_until(harness, client, None)["move_status"] == "succeeded"
    codes = _lift_codes(client)
    assert codes[:6] == ["01001", "04000", "04001", "04070", "04071", "04010"]
    assert codes[-1] == "01002"


def test_a_full_car_is_given_up_with_04033(harness: Harness, client: Client) -> None:
    """The only car to floor 3, full for good: given up (04033), queued for again twice (the
    only way there), then the move fails."""
    _car(harness).board_people(2)
    _ok(client, "/api/move?marker=room_301")
    assert _run_until(harness, client, None)["move_status"] == "failed"
    tries = ["04000", "04001", "04010", "04033"] * (1 + MAX_REQUEUES)
    assert _lift_codes(client) == ["01001", *tries, "01003"]


def test_a_car_that_does_not_come_within_3_minutes_sends_04013(
    harness: Harness, client: Client
) -> None:
    car = _car(harness)
    harness.runtime.request_lift("lift_1", LiftRequest("operator", "floor3"))
    harness.runtime.advance(15.0)
    harness.runtime.request_lift("lift_1", LiftRequest("operator", end_session=True))
    car.spec = replace(car.spec, speed=0.01)  # a lift stuck between floors
    _ok(client, "/api/move?marker=room_301")
    assert _run_until(harness, client, None)["move_status"] == "failed"
    # The router may first take lift_2 to floor 2 (lift_1 is expected late either way).
    codes = _lift_codes(client)
    assert codes[:4] == ["01001", "04000", "04001", "04010"]
    assert codes[-3:] == ["04010", "04013", "01003"]


def test_a_ride_over_3_minutes_sends_04023(harness: Harness, client: Client) -> None:
    _ok(client, "/api/move?marker=room_301")
    _run_until(harness, client, "take_lift")
    car = _car(harness)
    car.spec = replace(car.spec, speed=0.001)
    assert _run_until(harness, client, None)["move_status"] == "failed"
    codes = _lift_codes(client)
    assert codes[-4:] == ["04031", "04020", "04023", "01003"]
    assert "04021" not in codes


def _tries(codes: list[str]) -> list[list[str]]:
    """The lift codes of a move split into its tries of the car (each from ``04000``)."""
    tries: list[list[str]] = []
    for code in codes:
        if code == "04000":
            tries.append([])
        if tries and code.startswith("040"):
            tries[-1].append(code)
    return tries


def test_something_in_the_car_blocks_the_entry_with_04032_04040_04041(
    harness: Harness, client: Client
) -> None:
    """Each blocked entry gets out of the car's way (04040, ``avoid_lift``; back at the waiting
    spot, 04041) and tries again; the last one gives the car up (the only one: queued for
    again twice), then the move fails."""
    harness.runtime.simulation.place_obstacle("floor1", 37.0, 20.4, 0.35)
    _ok(client, "/api/move?marker=room_301")
    _run_until(harness, client, "avoid_lift")
    # Out of the way: back at the outside point, clear of the car's door.
    outside = harness.runtime.store.point("floor1", "lift_1_outside").pose
    _run_until(harness, client, "enter_lift")
    assert harness.runtime.simulation.true_pose.distance_to(outside) < 0.5
    assert _run_until(harness, client, None)["move_status"] == "failed"
    codes = _lift_codes(client)
    assert codes[0] == "01001" and codes[-1] == "01003"
    tries = _tries(codes)
    assert len(tries) == 1 + MAX_REQUEUES
    for codes_of_try in tries:
        assert codes_of_try[:5] == ["04000", "04001", "04010", "04011", "04030"]
        assert codes_of_try[5:] == ["04032", "04040", "04041"] * MAX_DOOR_RETRIES + ["04032"]


def test_a_blocked_way_to_the_door_sends_04002(harness: Harness, client: Client) -> None:
    """The car stuck away, the way to its door blocked: 04002 on each try (the only car to
    floor 3: queued for again twice), then failed. (A car already standing open is driven into
    straight from the waiting spot, so the blocked way only counts while the car is away.)"""
    car = _car(harness)
    harness.runtime.request_lift("lift_1", LiftRequest("operator", "floor3"))
    harness.runtime.advance(15.0)
    harness.runtime.request_lift("lift_1", LiftRequest("operator", end_session=True))
    car.spec = replace(car.spec, speed=1e-4)  # stuck between floors
    harness.runtime.set_lift_mode("lift_2", LiftMode.OUT_OF_SERVICE)  # no way round by floor 2
    harness.runtime.simulation.place_obstacle("floor1", 37.0, 17.6, 0.6)
    _ok(client, "/api/move?marker=room_301")
    assert _run_until(harness, client, None, 1500.0)["move_status"] == "failed"
    tries = ["04000", "04001", "04010", "04002"] * (1 + MAX_REQUEUES)
    assert _lift_codes(client) == ["01001", *tries, "01003"]


def test_a_blocked_way_out_goes_back_in_and_retries(harness: Harness, client: Client) -> None:
    _ok(client, "/api/move?marker=room_301")
    _run_until(harness, client, "take_lift")
    harness.runtime.simulation.place_obstacle("floor3", 37.0, 18.2, 0.7)
    assert _run_until(harness, client, None)["move_status"] == "failed"
    codes = _lift_codes(client)
    exit_part = codes[codes.index("04050"):]
    assert exit_part[:4] == ["04050", "04052", "04060", "04061"]
    assert exit_part[-1] == "01003" and "04051" not in exit_part


def test_a_way_back_into_the_car_blocked_too_sends_04062(
    harness: Harness, client: Client
) -> None:
    """The way out blocked, and while the robot turns back (``back_to_lift``) something is
    left in the car where it stood: each return fails (04062), each exit is tried again
    (04052, 04060) until the exit is given up (01003)."""
    _ok(client, "/api/move?marker=room_301")
    _run_until(harness, client, "take_lift")
    harness.runtime.simulation.place_obstacle("floor3", 37.0, 18.2, 0.7)
    _run_until(harness, client, "back_to_lift")
    harness.runtime.simulation.place_obstacle("floor3", 37.0, 20.6, 0.25)
    assert _run_until(harness, client, None)["move_status"] == "failed"
    assert harness.runtime.simulation.collisions == []
    codes = _lift_codes(client)
    exit_part = codes[codes.index("04050"):]
    assert exit_part == ["04050", *(["04052", "04060", "04062"] * MAX_DOOR_RETRIES), "01003"]


COVERED: dict[str, str] = {
    "notify 10 04070": "test_car_held_by_an_operator_waits_for_the_unlock",
    "notify 10 04071": "test_car_held_by_an_operator_waits_for_the_unlock",
    "notify 10 04033": "test_a_full_car_is_given_up_with_04033",
    "notify 10 04013": "test_a_car_that_does_not_come_within_3_minutes_sends_04013",
    "notify 10 04023": "test_a_ride_over_3_minutes_sends_04023",
    "notify 10 04032": "test_something_in_the_car_blocks_the_entry_with_04032_04040_04041",
    "notify 10 04040": "test_something_in_the_car_blocks_the_entry_with_04032_04040_04041",
    "notify 10 04041": "test_something_in_the_car_blocks_the_entry_with_04032_04040_04041",
    "notify 10 04062": "test_a_way_back_into_the_car_blocked_too_sends_04062",
    "notify 10 04002": "test_a_blocked_way_to_the_door_sends_04002",
    "notify 10 04052": "test_a_blocked_way_out_goes_back_in_and_retries",
    "notify 10 04060": "test_a_blocked_way_out_goes_back_in_and_retries",
    "notify 10 04061": "test_a_blocked_way_out_goes_back_in_and_retries",
}
