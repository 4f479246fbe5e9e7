"""Pydantic models of the task and schedule routes (``/api/tasks``, ``/api/schedules``).

A task's body is the tree's JSON form (Galileo's, galileo-tasks-bt-ws §7.2, which the native
API shares; :mod:`polynav.tasks.tree`): the schema types the root's fields, and the tree below
it is checked whole by the engine (a bad node is a 409 naming where, and nothing is made).
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field

from polynav.api.schemas import MAX_INTEGER, Integer

StateName = Literal["WAITTING", "WORKING", "PAUSED", "CANCELLED", "ERROR", "COMPLETE", "FAIL"]
def _integral(value: Any) -> Any:
    # As schemas.Integer: JSON Schema counts 12.0 as an integer, so the model must too.
    if isinstance(value, float) and value.is_integer():
        return int(value)
    return value


Count = Annotated[int, Field(strict=True, ge=0, le=MAX_INTEGER), BeforeValidator(_integral)]


class TaskIn(BaseModel):
    """A task tree: the root is a control node (a plain task is a sequence); other fields of
    the root are its control node's parameters (``success_count``, ``target_loop_count``)."""

    model_config = ConfigDict(extra="allow")

    name: str = Field(max_length=200, description="the task's name")
    control_type: str | None = Field(None, max_length=64,
                                     description="the root's control node; none: a sequence")
    sub_tasks: list[dict[str, Any] | str] = Field(
        max_length=2000, description="the root's children: nodes, or names from nodes")
    blackboard: dict[str, Any] | None = Field(None, description="the blackboard's starting "
                                              "values; {key} in string parameters is replaced")
    loop_flag: bool | None = Field(None, strict=True,
                                   description="a plain task runs again when it ends")
    nodes: dict[str, Any] | None = Field(None, description="named subtrees to use by name")

    def to_domain(self) -> dict[str, Any]:
        return self.model_dump(exclude_none=True)


class TaskOut(BaseModel):
    """A task as the engine shows it (``tree`` is the node tree with each node's state)."""

    id: str
    name: str
    owner: str
    kind: str
    state: StateName
    note: str = Field(description="why it ended as it did, when the tree does not say")
    temporary: bool
    blackboard: dict[str, Any]
    tree: dict[str, Any]

    @classmethod
    def from_domain(cls, snapshot: dict[str, Any]) -> TaskOut:
        return cls.model_validate(snapshot)


class LoopIn(BaseModel):
    model_config = ConfigDict(extra="forbid")

    loop: bool = Field(strict=True, description="whether the sequence runs again when it ends")
    node_id: str | None = Field(None, max_length=200,
                                description="a sequence node; none: the root")


class TriggeredOut(BaseModel):
    released: int = Field(description="how many waiting wait_req_action nodes were released")


class ScheduleSpecIn(BaseModel):
    """When to start the task: ``once`` at ``at``; ``weekly`` on ``weekdays`` at ``times``;
    ``monthly`` on ``days`` (1-31; months without the day are skipped) at ``times``. Date-times
    are the robot's local calendar, ``YYYY-MM-DDTHH:MM[:SS]``; times ``HH:MM[:SS]``."""

    model_config = ConfigDict(extra="forbid")

    mode: Literal["once", "weekly", "monthly"]
    at: str | None = Field(None, max_length=40)
    times: list[str] | None = Field(None, max_length=100)
    weekdays: list[str] | None = Field(None, max_length=7,
                                       description="monday ... sunday (or mon ... sun)")
    days: list[Integer] | None = Field(None, max_length=31)
    loop: Count = Field(0, description="how many times it starts the task; 0 for ever")
    enabled: bool = Field(True, strict=True)

    def to_domain(self) -> dict[str, Any]:
        return self.model_dump(exclude_none=True, exclude={"enabled"})


class ScheduleIn(ScheduleSpecIn):
    task_id: str = Field(min_length=1, max_length=200, description="the stored task to start")


class ScheduleLastOut(BaseModel):
    due: str | None
    outcome: Literal["started", "skipped"]
    reason: str


class ScheduleOut(BaseModel):
    id: str
    task_id: str
    mode: Literal["once", "weekly", "monthly"]
    loop: int
    at: str | None = None
    times: list[str] | None = None
    weekdays: list[str] | None = None
    days: list[int] | None = None
    enabled: bool
    starts: int = Field(description="starts made so far")
    next_fire: str | None = Field(description="the next due start; null when none is left")
    waiting: str | None = Field(description="a due start waiting for the robot to be free")
    last: ScheduleLastOut | None = Field(description="how the last due start went")
    updated: str

    @classmethod
    def from_domain(cls, data: dict[str, Any]) -> ScheduleOut:
        return cls.model_validate(data)
