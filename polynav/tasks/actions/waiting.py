"""Waiting: ``sleep_action`` (§5.3 #2) and ``wait_req_action`` (#8, §5.6), on the runtime's
clock. A pause stops the clock of the wait: resumed, it waits what was left."""

from __future__ import annotations

from typing import Any

from pydantic import Field

from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.states import NodeState

MAX_WAIT = 7 * 86_400.0  # [s]


class SleepParams(Params):
    wait_time: float = Field(ge=0.0, le=MAX_WAIT)


class _Wait(Action):
    def __init__(self, params: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(params, **kwargs)
        self.waited = 0.0
        self._since: float | None = None

    def limit(self) -> float | None:
        """How long to wait [s]; ``None``: until triggered."""
        return None

    def begin(self, run: Run) -> None:
        self._since = run.now

    def elapsed(self, run: Run) -> float:
        return self.waited + (0.0 if self._since is None else run.now - self._since)

    def poll(self, run: Run) -> NodeState | None:
        limit = self.limit()
        if limit is None:
            return None
        elapsed = self.elapsed(run)
        if elapsed + 1e-9 >= limit:
            return NodeState.COMPLETE
        self.fraction = elapsed / limit if limit > 0 else 0.0
        return None

    def hold(self, run: Run) -> None:
        self.waited = self.elapsed(run)
        self._since = None

    def carry_on(self, run: Run) -> None:
        self._since = run.now

    def reset(self) -> None:
        super().reset()
        self.waited = 0.0
        self._since = None


@action_type
class SleepAction(_Wait):
    """Wait ``wait_time`` seconds."""

    type = "sleep_action"
    schema = SleepParams

    def limit(self) -> float:
        assert isinstance(self.p, SleepParams)
        return self.p.wait_time


class WaitReqParams(Params):
    timeout: float = Field(default=0.0, ge=0.0, le=MAX_WAIT)


@action_type
class WaitReqAction(_Wait):
    """Wait until triggered (``update_wait_req``) or, with ``timeout`` > 0, that many
    seconds (A-14: seconds; COMPLETE either way). Blackboard: ``wait_req.triggered``
    (``True`` if triggered, ``False`` if it timed out)."""

    type = "wait_req_action"
    schema = WaitReqParams
    writes = ("wait_req.triggered",)

    def limit(self) -> float | None:
        assert isinstance(self.p, WaitReqParams)
        return self.p.timeout or None

    def poll(self, run: Run) -> NodeState | None:
        if run.triggers > 0:
            run.triggers -= 1
            run.blackboard.write("wait_req.triggered", True)
            return NodeState.COMPLETE
        state = super().poll(run)
        if state is not None:
            run.blackboard.write("wait_req.triggered", False)
        return state
