from __future__ import annotations

import json
from dataclasses import replace

from polynav.geometry import Pose2D
from polynav.localization.interface import PoseUncertainty
from polynav.runtime.status import StatusSnapshot


def _snapshot(**changes: object) -> StatusSnapshot:
    values: dict[str, object] = dict(
        mode="navigating", map="floor1", floor="floor1", pose=Pose2D(1.0, 2.0, 0.5),
        linear=0.25, angular=-0.5, battery_percent=80.0, charging=False, estop_hardware=False,
        estop_software=True, localization_state="tracking", localization_quality=0.75,
        navigation_state="running", stamp=12.5,
    )
    values.update(changes)
    return StatusSnapshot(**values)  # type: ignore[arg-type]


def test_to_dict_has_exactly_the_contract_keys() -> None:
    body = _snapshot().to_dict()
    assert set(body) == {"mode", "map", "floor", "floor_level", "pose", "velocity", "battery",
                         "estop", "localization", "navigation", "stamp", "frame", "mapping"}
    assert set(body["pose"]) == {"x", "y", "theta"}  # type: ignore[arg-type]
    assert set(body["velocity"]) == {"linear", "angular"}  # type: ignore[arg-type]
    assert set(body["battery"]) == {"percent", "charging"}  # type: ignore[arg-type]
    assert set(body["estop"]) == {"hardware", "software"}  # type: ignore[arg-type]
    assert set(body["localization"]) == {  # type: ignore[arg-type]
        "state", "quality", "uncertainty"}
    assert set(body["navigation"]) == {  # type: ignore[arg-type]
        "state", "goal", "reason", "distance_remaining", "phase", "retries",
        "arrival_uncertainty"}


def test_to_dict_shows_the_localization_and_arrival_uncertainty() -> None:
    body = replace(_snapshot(), localization_uncertainty=PoseUncertainty(0.02, 0.01),
                   arrival_uncertainty=PoseUncertainty(0.25, 0.005)).to_dict()
    assert body["localization"]["uncertainty"] == {  # type: ignore[index]
        "position": 0.02, "heading": 0.01}
    assert body["navigation"]["arrival_uncertainty"] == {  # type: ignore[index]
        "position": 0.25, "heading": 0.005}


def test_to_dict_values_for_a_running_goal_to_a_named_point() -> None:
    body = _snapshot(goal=Pose2D(5.5, 12.5, 0.0), goal_point="lobby", attempt_id=3,
                     distance_remaining=4.5, floor_level=1).to_dict()
    assert json.loads(json.dumps(body)) == {
        "mode": "navigating", "map": "floor1", "floor": "floor1", "floor_level": 1,
        "pose": {"x": 1.0, "y": 2.0, "theta": 0.5}, "frame": "map",
        "velocity": {"linear": 0.25, "angular": -0.5},
        "battery": {"percent": 80.0, "charging": False},
        "estop": {"hardware": False, "software": True},
        "localization": {"state": "tracking", "quality": 0.75, "uncertainty": None},
        "navigation": {"state": "running",
                       "goal": {"x": 5.5, "y": 12.5, "theta": 0.0, "point": "lobby"},
                       "reason": None, "distance_remaining": 4.5, "phase": None,
                       "retries": 0, "arrival_uncertainty": None},
        "stamp": 12.5, "mapping": None,
    }


def test_goal_is_null_without_an_attempt() -> None:
    nav = _snapshot(navigation_state="idle").to_dict()["navigation"]
    assert nav == {"state": "idle", "goal": None, "reason": None, "distance_remaining": None,
                   "phase": None, "retries": 0, "arrival_uncertainty": None}
