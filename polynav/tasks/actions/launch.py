"""``roslaunch_action`` (galileo-tasks-bt-ws §5.3 #11), simulated: nothing is started.

On the vendor's robot the action starts a ROS program (``roslaunch xiaoqiang_track
xiaoqiang_track.launch``) and completes once it has started (A-15). polynav runs no ROS
programs and must never run a command a task names (a task comes from any client), so the
action only records the command, in the log and on the blackboard, and completes: a tree
written for the vendor's robot runs on unchanged, and the record shows what it would have
started.

Blackboard: ``roslaunch.command``, the command as given (``{key}`` filled in).
"""

from __future__ import annotations

import logging

from pydantic import Field, field_validator

from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.states import NodeState

log = logging.getLogger(__name__)


class LaunchParams(Params):
    launch_cmd: str = Field(min_length=1, max_length=1024)

    @field_validator("launch_cmd")
    @classmethod
    def _one_line(cls, command: str) -> str:
        if not command.strip() or any(ord(c) < 32 for c in command):
            raise ValueError("must be one line of text")
        return command


@action_type
class RoslaunchAction(Action):
    """Record ``launch_cmd`` without running it (simulated, see the module); done at once."""

    type = "roslaunch_action"
    schema = LaunchParams
    writes = ("roslaunch.command",)

    def begin(self, run: Run) -> None:
        assert isinstance(self.p, LaunchParams)
        log.info("task %s: roslaunch (simulated, nothing started): %s", run.task_id,
                 self.p.launch_cmd)
        run.blackboard.write("roslaunch.command", self.p.launch_cmd)
        self.end(run, NodeState.COMPLETE, "simulated: nothing was started")
