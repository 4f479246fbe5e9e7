"""Action nodes: the leaves of a task tree, each driving one thing the robot does.

An action is made from its wire parameters (``{"type": "nav_action", "x": 1, ...}``), checked
then against its parameter model (a pydantic model: types, ranges, required fields), except
where a parameter is a ``{key}`` of the blackboard, whose value is known only when the action
starts. When it starts the parameters are filled in from the blackboard and checked again; a
parameter still wrong then ends the action ``ERROR`` (bad parameters). The parameters as given
are kept and echoed on the wire.

``FAIL`` or ``ERROR`` (galileo-tasks-bt-ws A-9): an action that cannot achieve its goal (a
navigation that fails: no path, blocked, stuck) ends ``FAIL`` so a parent can branch; a fault
(bad parameters, lost localization, the e-stop, a device fault) ends ``ERROR``, which stops the
tree.
"""

from __future__ import annotations

import builtins
import logging
from collections.abc import Mapping
from typing import Any, ClassVar

from pydantic import BaseModel, ConfigDict, ValidationError

from polynav.errors import InvalidRequest, PolynavError
from polynav.tasks.blackboard import is_placeholder
from polynav.tasks.node import Node, Run
from polynav.tasks.states import NodeState

log = logging.getLogger(__name__)


class Params(BaseModel):
    """Base of the parameter models: unknown fields are ignored (and echoed as given)."""

    model_config = ConfigDict(extra="ignore", frozen=True)


def _explain(exc: ValidationError, skip: set[str] = frozenset()) -> str | None:  # type: ignore[assignment]
    problems = []
    for error in exc.errors():
        loc = error.get("loc", ())
        if loc and loc[0] in skip:
            continue
        where = ".".join(str(part) for part in loc) or "parameters"
        problems.append(f"{where}: {error.get('msg', 'invalid')}")
    return "; ".join(problems) or None


class Action(Node):
    """Base of action nodes; subclasses give ``type``, ``Params`` and the hooks."""

    kind = "action"
    type: ClassVar[str] = ""
    schema: ClassVar[builtins.type[Params]] = Params
    #: Blackboard keys the action writes when it ends (documented per type).
    writes: ClassVar[tuple[str, ...]] = ()

    def __init__(self, params: Mapping[str, Any], *, name: str = "",
                 node_id: str | None = None) -> None:
        super().__init__(name=name, node_id=node_id)
        self.params: dict[str, Any] = {k: v for k, v in params.items()
                                       if k not in ("type", "id", "state", "result", "progress")}
        try:
            self.schema.model_validate(self.params)
        except ValidationError as exc:
            skip = {k for k, v in self.params.items() if is_placeholder(v)}
            problem = _explain(exc, skip)
            if problem is not None:
                raise InvalidRequest(self.type, problem) from None
        self.p: Params = self.schema.model_construct()
        self.fraction = 0.0

    @property
    def progress(self) -> float:
        if self.state is NodeState.COMPLETE:
            return 1.0
        return round(self.fraction, 3)

    def describe(self) -> dict[str, Any]:
        return {**super().describe(), "kind": self.type, "type": self.type,
                "params": dict(self.params), **self.live()}

    def live(self) -> dict[str, Any]:
        """What the action shows while it runs, beside its parameters."""
        return {}

    def reset(self) -> None:
        super().reset()
        self.fraction = 0.0

    # -- running -----------------------------------------------------------------------------

    def enter(self, run: Run) -> None:
        try:
            self.p = self.schema.model_validate(run.blackboard.fill(self.params))
        except ValidationError as exc:
            self.end(run, NodeState.ERROR, f"bad parameters: {_explain(exc)}")
            return
        try:
            self.begin(run)
        except PolynavError as exc:
            log.info("task %s: %s could not start: %s", run.task_id, self.type, exc)
            self.end(run, self.refused(exc), str(exc))

    def update(self, run: Run) -> None:
        try:
            state = self.poll(run)
        except PolynavError as exc:
            log.info("task %s: %s: %s", run.task_id, self.type, exc)
            self.end(run, self.refused(exc), str(exc))
            return
        if state is not None:
            self.end(run, state)

    def end(self, run: Run, state: NodeState, result: str | None = None) -> None:
        super().end(run, state, result)
        if state is NodeState.COMPLETE:
            self.fraction = 1.0

    def refused(self, exc: PolynavError) -> NodeState:
        """The state for a robot's refusal: a fault (``ERROR``) unless the type says it only
        means the goal cannot be achieved."""
        return NodeState.ERROR

    def begin(self, run: Run) -> None:
        """Start what the action drives (between ticks); may end it at once with
        :meth:`end`. Raises a polynav error when the robot refuses."""

    def poll(self, run: Run) -> NodeState | None:
        """The final state once the action is done, else ``None``."""
        return NodeState.COMPLETE


#: Action types by wire name (filled by :mod:`polynav.tasks.actions`).
ACTIONS: dict[str, type[Action]] = {}


def action_type(cls: type[Action]) -> type[Action]:
    """Register an action class under its ``type``."""
    assert cls.type and cls.type not in ACTIONS, cls.type
    ACTIONS[cls.type] = cls
    return cls
