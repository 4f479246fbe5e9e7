"""System state and GalileoStatus over real HTTP (galileo-http-a E-02, E-04; issue item 9)."""

from __future__ import annotations

import math

from polynav.geometry import Pose2D
from polynav.protocols.galileo.messages import SystemState
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.runtime.status import StatusSnapshot
from tests.protocols.galileo.conftest import Harness, serving

COVERED = {
    "GET /api/v1/system/status": "test_system_status_follows_the_runtime_mode",
    "GET /api/v1/system/galileo_status": "test_galileo_status_has_every_field_with_its_type",
}

FIELDS: dict[str, type | tuple[type, ...]] = {
    "header": dict, "navStatus": int, "visualStatus": int, "mapStatus": int, "gcStatus": int,
    "gbaStatus": int, "chargeStatus": int, "loopStatus": int, "power": float,
    "targetNumID": int, "targetStatus": int, "targetDistance": float, "angleGoalStatus": int,
    "controlSpeedX": float, "controlSpeedTheta": float, "currentSpeedX": float,
    "currentSpeedTheta": float, "currentPosX": float, "currentPosY": float,
    "currentAngle": float, "busyStatus": int,
}


def test_system_status_follows_the_runtime_mode(runtime: RobotRuntime) -> None:
    with serving(runtime) as g:
        body = g.ok("GET", "/system/status")
        assert body == {"status": "Free"}
        map_name = runtime.store.maps()[0].name
        runtime.start_navigation(map_name)
        assert g.ok("GET", "/system/status") == {"status": SystemState.NAVIGATING.value}
        runtime.stop_navigation()
        runtime.advance(0.1)
        assert g.ok("GET", "/system/status") == {"status": "Free"}


def test_galileo_status_has_every_field_with_its_type(galileo: Harness) -> None:
    body = galileo.ok("GET", "/system/galileo_status")
    assert list(body) == list(FIELDS), "fields in the document's order"
    for name, kind in FIELDS.items():
        assert isinstance(body[name], kind), (name, body[name])
        assert not isinstance(body[name], bool), name
    header = body["header"]
    assert header["frame_id"] == "map"
    assert set(header["stamp"]) == {"secs", "nsecs"}
    assert isinstance(header["seq"], int)
    # Free robot: navigation closed, visual system off, no target.
    assert body["navStatus"] == 0 and body["mapStatus"] == 0 and body["busyStatus"] == 0
    assert body["visualStatus"] == -1
    assert (body["targetNumID"], body["targetStatus"], body["targetDistance"]) == (-1, -1, -1.0)
    assert body["angleGoalStatus"] == -1
    assert 20.0 < body["power"] < 60.0  # a pack voltage, not a percentage
    pose = galileo.runtime.status().pose
    assert math.isclose(body["currentPosX"], pose.x, abs_tol=1e-6)
    assert math.isclose(body["currentAngle"], pose.theta, abs_tol=1e-6)
    again = galileo.ok("GET", "/system/galileo_status")
    assert again["header"]["seq"] > header["seq"]


def test_galileo_status_while_navigating_reads_opened_and_tracking(galileo: Harness) -> None:
    runtime = galileo.runtime
    runtime.start_navigation(runtime.store.maps()[0].name)
    runtime.advance(1.0)
    body = galileo.ok("GET", "/system/galileo_status")
    assert body["navStatus"] == 1
    assert body["visualStatus"] in (1, 2)
    stamp = body["header"]["stamp"]
    assert abs(stamp["secs"] + stamp["nsecs"] / 1e9 - runtime.status().stamp) < 1.0


def _snapshot(**changes: object) -> StatusSnapshot:
    base: dict[str, object] = dict(
        mode="navigating", map="m", floor="f", pose=Pose2D(1.0, 2.0, 0.5), linear=0.3,
        angular=0.1, battery_percent=50.0, charging=False, estop_hardware=False,
        estop_software=False, localization_state="tracking", localization_quality=0.9,
        navigation_state="running", stamp=12.25, attempt_id=7, goal=Pose2D(4.0, 6.0, 0.0),
        distance_remaining=5.5,
    )
    base.update(changes)
    return StatusSnapshot(**base)  # type: ignore[arg-type]


def test_target_fields_follow_the_attempt_states() -> None:
    from polynav.protocols.galileo.context import Target
    from polynav.protocols.galileo.status import target_fields

    running = target_fields(_snapshot(), Target(3, "m", "p"))
    assert running == {"targetNumID": 3, "targetStatus": 1, "targetDistance": 5.5,
                       "angleGoalStatus": 0}
    assert target_fields(_snapshot(), None)["targetNumID"] == -2
    assert target_fields(_snapshot(navigation_state="paused"), None)["targetStatus"] == 2
    done = target_fields(_snapshot(navigation_state="succeeded"), None)
    assert (done["targetStatus"], done["targetDistance"], done["angleGoalStatus"]) == (0, 0.0, 1)
    failed = target_fields(_snapshot(navigation_state="failed"), None)
    assert (failed["targetStatus"], failed["angleGoalStatus"]) == (3, 2)
    idle = target_fields(_snapshot(navigation_state="idle", attempt_id=None), None)
    assert idle == {"targetNumID": -1, "targetStatus": -1, "targetDistance": -1.0,
                    "angleGoalStatus": -1}


def test_charge_and_visual_status_enums() -> None:
    from polynav.protocols.galileo.context import Target
    from polynav.protocols.galileo.status import charge_status, visual_status

    assert charge_status(_snapshot(charging=True), None) == 1
    assert charge_status(_snapshot(charging=True, battery_percent=100.0), None) == 2
    assert charge_status(_snapshot(), Target(-1)) == 3
    assert charge_status(_snapshot(phase="dock"), Target(-1)) == 4
    assert charge_status(_snapshot(phase="dock", navigation_state="failed"), Target(-1)) == 5
    assert charge_status(_snapshot(), None) == 0
    assert visual_status(_snapshot(mode="free")) == -1
    assert visual_status(_snapshot(localization_state="uninitialized")) == 0
    assert visual_status(_snapshot()) == 1
    assert visual_status(_snapshot(localization_state="lost")) == 2
    assert visual_status(_snapshot(localization_quality=0.05)) == 2
