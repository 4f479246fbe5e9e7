from __future__ import annotations

import json
import re

from polynav.geometry import Pose2D
from polynav.runtime import events


def _event_classes() -> list[type[events.RuntimeEvent]]:
    return [
        cls for cls in vars(events).values()
        if isinstance(cls, type) and issubclass(cls, events.RuntimeEvent)
        and cls.kind != events.RuntimeEvent.kind  # not a base (RuntimeEvent, AttemptEvent...)
    ]


def test_every_event_kind_is_unique_snake_case() -> None:
    kinds = [cls.kind for cls in _event_classes()]
    assert len(kinds) >= 14
    assert len(set(kinds)) == len(kinds)
    assert all(re.fullmatch(r"[a-z]+(_[a-z]+)*", k) for k in kinds), kinds


def test_to_dict_writes_poses_as_xy_theta_and_the_kind() -> None:
    event = events.NavigationStarted(2.5, 7, Pose2D(1.0, 2.0, 0.5), "lobby")
    assert event.to_dict() == {
        "kind": "navigation_started",
        "stamp": 2.5,
        "attempt_id": 7,
        "goal": {"x": 1.0, "y": 2.0, "theta": 0.5},
        "point": "lobby",
    }


def test_to_dict_is_json_ready_for_every_field_type() -> None:
    samples = [
        events.ModeChanged(0.0, "free", "busy"),
        events.NavigationFailed(1.0, 3, "no path", 2.25),
        events.EStopChanged(1.5, False, True, True),
        events.LocalizationChanged(2.0, "lost", 0.125),
        events.PoseInitialized(3.0, Pose2D(0.0, 1.0, -1.0)),
    ]
    decoded = [json.loads(json.dumps(e.to_dict())) for e in samples]
    assert decoded[1] == {"kind": "navigation_failed", "stamp": 1.0, "attempt_id": 3,
                          "reason": "no path", "distance": 2.25, "planned": True}
    assert decoded[2] == {"kind": "estop_changed", "stamp": 1.5, "hardware": False,
                          "software": True, "active": True}
    assert decoded[4]["pose"] == {"x": 0.0, "y": 1.0, "theta": -1.0}
