"""``blockly_action`` (galileo-tasks-bt-ws §5.3 #15): trigger the automation task whose API
block carries ``api_key``.

Done once the trigger is sent (the document: it "triggers the matching automation"), not when
the program ends: an automation may run far longer than the task. No enabled automation with
that key ends ``FAIL``; automations switched off, or that automation already running, end
``ERROR`` (the robot is not set up for it). Blackboard: ``blockly.run_id``, the run started.
"""

from __future__ import annotations

from pydantic import Field

from polynav.errors import NotFound, PolynavError
from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.states import NodeState


class BlocklyParams(Params):
    api_key: str = Field(min_length=1, max_length=200)


@action_type
class BlocklyAction(Action):
    """Trigger an automation by its key."""

    type = "blockly_action"
    schema = BlocklyParams
    writes = ("blockly.run_id",)

    def begin(self, run: Run) -> None:
        assert isinstance(self.p, BlocklyParams)
        run_id = run.robot.trigger_automation(self.p.api_key)
        run.blackboard.write("blockly.run_id", run_id)
        self.end(run, NodeState.COMPLETE)

    def refused(self, exc: PolynavError) -> NodeState:
        return NodeState.FAIL if isinstance(exc, NotFound) else NodeState.ERROR
