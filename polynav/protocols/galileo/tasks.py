"""The task and action endpoints (galileo-tasks-bt-ws §4, §5): Galileo's tasks, behavior trees
and actions, on the robot's task engine (``runtime.tasks``, :mod:`.task_objects` translates).

Decisions where the document is silent (§3.2, §11):

* One task runs at a time; starting one pre-empts the running one (A-6). ``start`` of a task
  that runs (or is paused) is refused; a task that ended runs again from its start.
* ``pause`` only a working task, ``resume`` only a paused one; otherwise refused (409).
* ``PUT /task`` and every change of a task's actions are refused while it runs or is paused;
  ``sub_tasks`` replace the old ones when given (A-7). A behavior tree keeps its
  ``control_type`` unless one is given; a plain task stays plain.
* ``POST /action`` without ``task_id`` makes a temporary ``"auto task"`` (A-13): ``WAITTING``,
  not listed by ``GET /task``, started by id. With ``task_id`` the action is appended.
* Without ``id``, ``GET /task`` and ``GET /action`` answer arrays, and ``/task/stop`` cancels
  the running task and answers the array of the tasks cancelled (A-5).
* ``update_wait_req`` releases every waiting ``wait_req_action`` and answers
  ``{"status": "OK"}`` (A-11, A-14).
* A task keeps at least one action (the engine's control nodes take one child or more):
  a task is made with its ``sub_tasks``, and deleting its last action is refused.

Device jobs shown as tasks (slide, jacking, video: :mod:`.system_tasks`) answer ``GET /task?id=``
and ``/task/stop?id=`` under their own ids.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping
from typing import Any

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.protocols.galileo import system_tasks
from polynav.protocols.galileo import task_objects as objects
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.tasks import tree
from polynav.tasks.action import ACTIONS
from polynav.tasks.control import Control
from polynav.tasks.engine import Task
from polynav.tasks.node import Node

log = logging.getLogger(__name__)

ROUTES = RouteList()

AUTO_TASK_NAME = "auto task"


def _listed(ctx: Context) -> list[dict[str, Any]]:
    """The snapshots of the Galileo tasks ``GET /task`` lists (temporary ones are not)."""
    return [s for s in ctx.runtime.tasks.list(owner=objects.OWNER) if not s["temporary"]]


# -- tasks ---------------------------------------------------------------------------------


@ROUTES.get("/task", inline=True)
def get_task(ctx: Context, params: Params) -> Reply:
    """§4.1: one task object, or every task in an array."""
    task_id = params.text("id", None)
    if task_id is None:
        return [objects.render(s) for s in _listed(ctx)]
    try:
        return objects.render(ctx.runtime.tasks.get(task_id))
    except NotFound:
        device = system_tasks.device_task(ctx, task_id)  # a slide, jacking or video task
        if device is None:
            raise
        return device


@ROUTES.post("/task")
def post_task(ctx: Context, params: Params) -> Reply:
    """§4.2, §7.2: a task, or a behavior tree with ``control_type``, made ``WAITTING``."""
    params.text("name")
    body = objects.body_of(params)
    kind = objects.TREE if "control_type" in body else objects.TASK
    return objects.render(objects.create(ctx, objects.tree_spec(ctx, body), kind=kind))


@ROUTES.put("/task")
def put_task(ctx: Context, params: Params) -> Reply:
    """§4.3: change the name, ``loop_flag`` and ``sub_tasks`` of a task that does not run."""
    task_id = params.text("id")
    name = params.text("name", None)
    loop = params.boolean("loop_flag", None)
    snapshot = ctx.runtime.tasks.get(task_id)
    root_kind = snapshot["tree"]["kind"]
    body = {k: v for k, v in objects.body_of(params).items() if k != "id"}
    spec: dict[str, Any] | None = None
    if "sub_tasks" in body:
        if "control_type" in body and snapshot["kind"] != objects.TREE:
            raise InvalidRequest("control_type", "a plain task stays plain: make a behavior "
                                                 "tree with POST /api/v1/task")
        spec = {"name": name if name is not None else snapshot["name"], **body}
        if snapshot["kind"] == objects.TREE:
            spec.setdefault("control_type", root_kind)
        if loop is not None:
            spec["loop_flag"] = loop
        elif "loop_flag" in snapshot["tree"]:
            spec["loop_flag"] = snapshot["tree"]["loop_flag"]
        spec = objects.tree_spec(ctx, spec)
        root_kind = spec.get("control_type", "sequence")
    if loop is not None and root_kind != "sequence":
        raise InvalidRequest("loop_flag", f"a {root_kind} node does not loop by flag")
    changed = ctx.runtime.tasks.replace(task_id, spec, name=name)  # refused while it runs
    if loop is not None and spec is None:
        changed = ctx.runtime.tasks.set_loop(task_id, loop)
    return objects.render(changed)


@ROUTES.delete("/task")
def delete_task(ctx: Context, params: Params) -> Reply:
    """§4.4: forget a task that does not run."""
    ctx.runtime.tasks.delete(params.text("id"))
    return {"status": "ok"}


@ROUTES.get("/task/start")
def start_task(ctx: Context, params: Params) -> Reply:
    """§4.5: run the task from its start (pre-empting the running one); the task after."""
    return objects.render(ctx.runtime.tasks.start(params.text("id")))


@ROUTES.get("/task/pause")
def pause_task(ctx: Context, params: Params) -> Reply:
    """§4.6."""
    return objects.render(ctx.runtime.tasks.pause(params.text("id")))


@ROUTES.get("/task/resume")
def resume_task(ctx: Context, params: Params) -> Reply:
    """§4.7."""
    return objects.render(ctx.runtime.tasks.resume(params.text("id")))


@ROUTES.get("/task/stop")
def stop_task(ctx: Context, params: Params) -> Reply:
    """§4.8: cancel the task (a device task too); without ``id`` the running task, answered
    as an array of the tasks cancelled."""
    task_id = params.text("id", None)
    if task_id is None:
        cancelled = ctx.runtime.tasks.cancel_running()
        return [] if cancelled is None else [objects.render(cancelled)]
    try:
        return objects.render(ctx.runtime.tasks.cancel(task_id))
    except NotFound:
        device = system_tasks.stop_device_task(ctx, task_id)
        if device is None:
            raise
        return device


@ROUTES.get("/task/loop")
def loop_task(ctx: Context, params: Params) -> Reply:
    """§4.9: set ``loop_flag`` (A-8: true/false, 1/0 in any case); the task after."""
    loop = params.boolean("loop_flag")
    return objects.render(ctx.runtime.tasks.set_loop(params.text("id"), loop))


# -- actions ---------------------------------------------------------------------------------


def _find_action(ctx: Context, action_id: str) -> tuple[dict[str, Any], Mapping[str, Any]]:
    """(the snapshot of the Galileo task holding action ``action_id``, the action's node).

    Raises:
        NotFound: no Galileo task holds it.
    """
    for snapshot in ctx.runtime.tasks.list(owner=objects.OWNER):
        for node in objects.leaves(snapshot):
            if node["id"] == action_id:
                return snapshot, node
    raise NotFound("action", action_id)


def _edit(ctx: Context, task_id: str, change: Callable[[Node], None]) -> dict[str, Any]:
    """Change the tree of a Galileo task that does not run, between ticks; its snapshot.

    Raises:
        NotFound: no such Galileo task.
        Conflict: it runs or is paused.
        InvalidRequest: ``change`` refused (it checks before it changes anything).
    """
    engine = ctx.runtime.tasks.engine

    def apply() -> Task:
        task = engine.find(task_id)
        if task.owner != objects.OWNER:
            raise NotFound("task", task_id)
        if task.state.active:
            raise Conflict(f"task {task_id} is {task.state.value}: stop it first")
        change(task.root)
        return engine.replace(task_id, task.root)  # shows the change

    return ctx.runtime.run_between_ticks(apply).snapshot


def _parent(root: Node, node_id: str) -> tuple[Control, int]:
    for node in root.walk():
        for i, child in enumerate(node.children):
            if child.id == node_id:
                assert isinstance(node, Control)
                return node, i
    raise NotFound("action", node_id)


def _children_fit(node: Node, count: int) -> None:
    """Refuse leaving ``node`` with ``count`` children when its kind takes another number."""
    if not isinstance(node, Control):
        raise InvalidRequest("task_id", f"a {node.kind} node has no children")
    least, most = node.arity
    if count < least or (most is not None and count > most):
        wanted = f"exactly {least}" if least == most else f"at least {least}"
        raise InvalidRequest("sub_tasks", f"a {node.kind} node takes {wanted} "
                                          f"child{'ren' if least != 1 else ''}")


@ROUTES.get("/action", inline=True)
def get_action(ctx: Context, params: Params) -> Reply:
    """§5.1: one action, or every action of the tasks ``GET /task`` lists, in an array."""
    action_id = params.text("id", None)
    if action_id is None:
        return [objects.render_node(node, tree=s["kind"] == objects.TREE)
                for s in _listed(ctx) for node in objects.leaves(s)]
    snapshot, node = _find_action(ctx, action_id)
    return objects.render_node(node, tree=snapshot["kind"] == objects.TREE)


@ROUTES.post("/action")
def post_action(ctx: Context, params: Params) -> Reply:
    """§5.2: an action appended to task ``task_id``, else in a new temporary ``"auto task"``;
    the task that holds it."""
    params.text("type")
    task_id = params.text("task_id", None)
    body = {k: v for k, v in objects.body_of(params).items() if k != "task_id"}
    spec = objects.action_spec(ctx, body)
    if task_id is None:
        return objects.render(objects.create(
            ctx, {"name": AUTO_TASK_NAME, "sub_tasks": [spec]}, kind=objects.AUTO,
            temporary=True))
    action = tree.build(spec)

    def append(root: Node) -> None:
        _children_fit(root, len(root.children) + 1)
        root.children.append(action)

    return objects.render(_edit(ctx, task_id, append))


@ROUTES.put("/action")
def put_action(ctx: Context, params: Params) -> Reply:
    """§5.4: change parameters of an action whose task does not run; the action after."""
    action_id = params.text("id")
    snapshot, node = _find_action(ctx, action_id)
    body = {k: v for k, v in objects.body_of(params).items() if k != "id"}
    if body.get("type", node["type"]) != node["type"]:
        raise InvalidRequest("type", "an action keeps its type: delete it and add another")
    spec = objects.action_spec(ctx, {**node["params"], **body, "type": node["type"]})
    try:
        action = ACTIONS[node["type"]](spec, name=node["name"], node_id=action_id)
    except InvalidRequest as exc:
        raise InvalidRequest(f"{node['type']}.{exc.field}", exc.reason) from None

    def swap(root: Node) -> None:
        parent, i = _parent(root, action_id)
        parent.children[i] = action

    changed = _edit(ctx, snapshot["id"], swap)
    tree_kind = changed["kind"] == objects.TREE
    return next(objects.render_node(n, tree=tree_kind) for n in objects.leaves(changed)
                if n["id"] == action_id)


@ROUTES.delete("/action")
def delete_action(ctx: Context, params: Params) -> Reply:
    """§5.5: remove an action from a task that does not run."""
    action_id = params.text("id")
    snapshot, _node = _find_action(ctx, action_id)

    def remove(root: Node) -> None:
        parent, i = _parent(root, action_id)
        _children_fit(parent, len(parent.children) - 1)
        del parent.children[i]

    _edit(ctx, snapshot["id"], remove)
    return {"status": "ok"}


@ROUTES.get("/action/update_wait_req")
def update_wait_req(ctx: Context, params: Params) -> Reply:
    """§5.6: release every waiting ``wait_req_action`` of the running task."""
    released = ctx.runtime.tasks.trigger_waits()
    log.info("galileo: update_wait_req released %d waiting action(s)", released)
    return {"status": "OK"}
