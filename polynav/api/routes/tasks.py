"""Tasks: behaviour trees the robot runs (make, list, start, pause, resume, cancel, replace,
delete, loop, trigger). Each route is one call of ``runtime.tasks``; a task made here is the
``native`` owner's and kept in the site store."""

from __future__ import annotations

import logging
from typing import Annotated

from fastapi import APIRouter, Body, Path, Query, Response

from polynav.api.deps import RuntimeDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.examples import NAP_TASK, examples, link, links
from polynav.api.schemas_tasks import LoopIn, TaskIn, TaskOut, TriggeredOut

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/tasks", tags=["tasks"], responses=LOOKUP)

TaskId = Annotated[str, Path(min_length=1, max_length=200, description="the task's id")]
TaskBody = Annotated[TaskIn, Body(openapi_examples=examples(a_nap=NAP_TASK))]
# Only a new task has an example: the others name a task by its id, made at run time (a uuid),
# which no example can know; the links below hand it on instead.
# A task made leads to what can be done with it: its start, and a schedule that starts it.
_MADE = "$response.body#/id"
MADE = links(
    StartMadeTask=link("start_task", parameters={"task_id": _MADE},
                       description="run the task just made"),
    ScheduleMadeTask=link("create_schedule", body={"task_id": _MADE},
                          description="start the task just made on the robot's calendar"),
)
NodeId = Annotated[str | None, Query(max_length=200,
                                     description="a node of the task (at any depth)")]


@router.get("", operation_id="list_tasks", response_model=list[TaskOut])
def list_tasks(runtime: RuntimeDep) -> list[TaskOut]:
    """Every task of the robot, whoever made it."""
    return [TaskOut.from_domain(t) for t in runtime.tasks.list()]


@router.post("", operation_id="create_task", response_model=TaskOut, status_code=201,
             responses=responses(BODY, STATE, {201: MADE}))
def create_task(body: TaskBody, runtime: RuntimeDep,
                start: Annotated[bool, Query(description="start it at once")] = False
                ) -> TaskOut:
    """Make a task from its tree (409 naming the node for a bad tree; nothing is made)."""
    return TaskOut.from_domain(runtime.tasks.create(body.to_domain(), start=start))


@router.get("/{task_id}", operation_id="get_task", response_model=TaskOut)
def get_task(task_id: TaskId, runtime: RuntimeDep) -> TaskOut:
    return TaskOut.from_domain(runtime.tasks.get(task_id))


@router.put("/{task_id}", operation_id="replace_task", response_model=TaskOut,
            responses=responses(BODY, STATE))
def replace_task(task_id: TaskId, body: TaskIn, runtime: RuntimeDep) -> TaskOut:
    """Replace the tree, name and blackboard of a task that does not run (409 if it does)."""
    spec = body.to_domain()
    return TaskOut.from_domain(runtime.tasks.replace(
        task_id, spec, name=body.name, blackboard=body.blackboard or {}))


@router.delete("/{task_id}", operation_id="delete_task", status_code=204, responses=STATE)
def delete_task(task_id: TaskId, runtime: RuntimeDep) -> Response:
    """Forget a task that does not run, with its schedules."""
    runtime.tasks.delete(task_id)
    return Response(status_code=204)


@router.post("/{task_id}/start", operation_id="start_task", response_model=TaskOut,
             responses=STATE)
def start_task(task_id: TaskId, runtime: RuntimeDep) -> TaskOut:
    """Run the task from its start, pre-empting a running one (409 if it runs already)."""
    return TaskOut.from_domain(runtime.tasks.start(task_id))


@router.post("/{task_id}/pause", operation_id="pause_task", response_model=TaskOut,
             responses=STATE)
def pause_task(task_id: TaskId, runtime: RuntimeDep, node_id: NodeId = None) -> TaskOut:
    return TaskOut.from_domain(runtime.tasks.pause(task_id, node_id))


@router.post("/{task_id}/resume", operation_id="resume_task", response_model=TaskOut,
             responses=STATE)
def resume_task(task_id: TaskId, runtime: RuntimeDep, node_id: NodeId = None) -> TaskOut:
    return TaskOut.from_domain(runtime.tasks.resume(task_id, node_id))


@router.post("/{task_id}/cancel", operation_id="cancel_task", response_model=TaskOut,
             responses=STATE)
def cancel_task(task_id: TaskId, runtime: RuntimeDep, node_id: NodeId = None) -> TaskOut:
    """Cancel the task, or one node of it (its parent takes that as a failed child)."""
    return TaskOut.from_domain(runtime.tasks.cancel(task_id, node_id))


@router.put("/{task_id}/loop", operation_id="set_task_loop", response_model=TaskOut,
            responses=responses(BODY, STATE))
def set_task_loop(task_id: TaskId, body: LoopIn, runtime: RuntimeDep) -> TaskOut:
    """Set ``loop_flag`` of the root (kept) or of a sequence node (this run)."""
    return TaskOut.from_domain(runtime.tasks.set_loop(task_id, body.loop, body.node_id))


@router.post("/{task_id}/trigger", operation_id="trigger_task", response_model=TriggeredOut,
             responses=STATE)
def trigger_task(task_id: TaskId, runtime: RuntimeDep) -> TriggeredOut:
    """Release the waiting ``wait_req_action`` nodes of this task, which must be the running
    one (Galileo's ``update_wait_req``; 409 otherwise). A path per task, not ``/trigger``
    beside ``/{task_id}``: one path, one set of methods (the 405 ``Allow`` header)."""
    return TriggeredOut(released=runtime.tasks.trigger_waits(task_id))
