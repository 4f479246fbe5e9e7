"""``callback_action`` (galileo-tasks-bt-ws §5.3 #1): the robot sends ``data`` to ``url`` with
``method`` and goes on once answered.

The request is sent off the control loop (the runtime's worker, :mod:`polynav.runtime
.http_callbacks`) and the action asks each tick whether it was answered, so a slow server never
stalls the robot. ``COMPLETE`` on a 2xx answer; ``FAIL`` on any other answer, a network error or
no answer within ``timeout`` seconds (the document gives no failure, A-9: a server that is down
is a goal not reached, for a fallback to branch on). A host the runtime does not allow
(loopback only unless ``RuntimeConfig.task_callback_hosts`` says more) is ``ERROR`` when the
action starts: a bad parameter, not a passing failure. Cancelling forgets the answer.

Blackboard: ``callback.status`` (the HTTP status, 0 with no answer) and ``callback.body`` (the
answer's text, at most 4096 characters).
"""

from __future__ import annotations

from typing import Any
from urllib.parse import urlsplit

from pydantic import Field, field_validator

from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.states import NodeState

METHODS = ("GET", "POST", "PUT", "PATCH", "DELETE")


class CallbackParams(Params):
    url: str = Field(min_length=1, max_length=2048)
    method: str = "POST"
    data: dict[str, Any] = Field(default_factory=dict)
    timeout: float = Field(default=10.0, gt=0.0, le=300.0)

    @field_validator("url")
    @classmethod
    def _http(cls, url: str) -> str:
        try:
            parts = urlsplit(url)
        except ValueError as exc:
            raise ValueError(f"not a URL: {exc}") from None
        if parts.scheme not in ("http", "https") or not parts.hostname:
            raise ValueError("must be an http:// or https:// URL with a host")
        return url

    @field_validator("method")
    @classmethod
    def _method(cls, method: str) -> str:
        if method.upper() not in METHODS:
            raise ValueError(f"must be one of {', '.join(METHODS)}")
        return method.upper()


@action_type
class CallbackAction(Action):
    """Send ``data`` to ``url`` with ``method`` (default ``POST``: a JSON body; ``GET`` and
    ``DELETE`` send it as the query string); done on a 2xx answer."""

    type = "callback_action"
    schema = CallbackParams
    writes = ("callback.status", "callback.body")

    def __init__(self, params: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(params, **kwargs)
        self.call_id: int | None = None

    def begin(self, run: Run) -> None:
        p = self.p
        assert isinstance(p, CallbackParams)
        self.call_id = run.robot.start_callback(p.url, p.method, p.data, p.timeout)

    def poll(self, run: Run) -> NodeState | None:
        assert self.call_id is not None
        answer = run.robot.callback_answer(self.call_id)
        if answer is None:
            return None
        run.robot.drop_callback(self.call_id)
        self.call_id = None
        run.blackboard.write("callback.status", answer.status)
        run.blackboard.write("callback.body", answer.body)
        if answer.error:
            self.result = answer.error
            return NodeState.FAIL
        if not 200 <= answer.status < 300:
            self.result = f"HTTP {answer.status}"
            return NodeState.FAIL
        return NodeState.COMPLETE

    def halt(self, run: Run) -> None:
        if self.call_id is not None:
            run.robot.drop_callback(self.call_id)
            self.call_id = None

    def reset(self) -> None:
        super().reset()
        self.call_id = None

    def live(self) -> dict[str, Any]:
        return {"callback_id": self.call_id}
