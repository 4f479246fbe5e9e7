"""Waiting for the battery: ``battery_wait_action`` (polynav's own type).

The robot stands on its charger until the battery holds ``percent`` (auto-charge's "charge to
full"). It fails if charging stops before (the robot was moved off the contacts, the charger
gave out) or after ``timeout`` seconds (0: none): standing on a dead charger for ever helps no
one. Blackboard: ``battery.percent`` when it ends.
"""

from __future__ import annotations

from typing import Any

from pydantic import Field

from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.states import NodeState


class BatteryWaitParams(Params):
    percent: float = Field(gt=0.0, le=100.0)
    timeout: float = Field(default=0.0, ge=0.0)


@action_type
class BatteryWaitAction(Action):
    """Wait on the charger until the battery reaches ``percent``."""

    type = "battery_wait_action"
    schema = BatteryWaitParams
    writes = ("battery.percent",)

    def __init__(self, params: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(params, **kwargs)
        self.since = 0.0
        self.start_percent = 0.0

    def begin(self, run: Run) -> None:
        self.since = run.now
        self.start_percent = run.robot.battery_percent()

    def poll(self, run: Run) -> NodeState | None:
        p = self.p
        assert isinstance(p, BatteryWaitParams)
        percent = run.robot.battery_percent()
        if percent >= p.percent:
            run.blackboard.write("battery.percent", round(percent, 1))
            return NodeState.COMPLETE
        if not run.robot.charging():
            self.result = f"charging stopped at {percent:.1f} %"
            return NodeState.FAIL
        if p.timeout and run.now - self.since > p.timeout:
            self.result = f"still {percent:.1f} % after {p.timeout:g} s on the charger"
            return NodeState.FAIL
        span = p.percent - self.start_percent
        self.fraction = (percent - self.start_percent) / span if span > 0 else 0.0
        return None
