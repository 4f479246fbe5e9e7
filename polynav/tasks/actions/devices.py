"""Actions on the robot's devices and settings: ``io_action``, ``tts_action`` and
``change_setting_action`` (§5.3 #12, #24, #10)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.states import NodeState


class IoParams(Params):
    level: Literal["0", "1", 0, 1]
    port: Literal["1", "2", "3", 1, 2, 3]


@action_type
class IoAction(Action):
    """Set output ``port`` ("1"-"3") of the base's IO to ``level`` ("0" low, "1" high); done
    once set (the wire types are the documented strings; numbers are taken too)."""

    type = "io_action"
    schema = IoParams

    def begin(self, run: Run) -> None:
        assert isinstance(self.p, IoParams)
        run.robot.set_output(int(self.p.port), int(self.p.level))
        self.end(run, NodeState.COMPLETE)


class SayParams(Params):
    text: str = Field(max_length=4096)


@action_type
class TtsAction(Action):
    """Speak ``text`` (``{key}`` from the blackboard); done when speaking ends. Blackboard:
    ``tts.text``, the text spoken."""

    type = "tts_action"
    schema = SayParams
    writes = ("tts.text",)

    def __init__(self, params: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(params, **kwargs)
        self.until = 0.0

    def begin(self, run: Run) -> None:
        assert isinstance(self.p, SayParams)
        self.until = run.now + run.robot.say(self.p.text)
        run.blackboard.write("tts.text", self.p.text)

    def poll(self, run: Run) -> NodeState | None:
        return NodeState.COMPLETE if run.now + 1e-9 >= self.until else None

    def halt(self, run: Run) -> None:
        run.robot.stop_speaking()


class SettingParams(Params):
    settings: dict[str, Any]
    init_settings: dict[str, Any] | None = None


@action_type
class ChangeSettingAction(Action):
    """Apply ``settings``; with ``init_settings`` those are applied when the task ends, however
    it ends (§3.1: restored when the task completes or is cancelled)."""

    type = "change_setting_action"
    schema = SettingParams

    def begin(self, run: Run) -> None:
        assert isinstance(self.p, SettingParams)
        run.robot.change_settings(self.p.settings)
        if self.p.init_settings is not None:
            run.restore.append(dict(self.p.init_settings))
        self.end(run, NodeState.COMPLETE)
