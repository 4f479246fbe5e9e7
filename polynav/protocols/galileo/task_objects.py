"""Galileo task objects over the robot's task engine (galileo-tasks-bt-ws §2-5, §7).

The engine (``runtime.tasks``) keeps and runs every task; this module only translates, both
ways, and is what the other route modules use to make and control their tasks.

* Inbound (:func:`tree_spec`, :func:`action_spec`): a Galileo task, behavior tree or action body
  is already the engine's tree form, so little changes. A ``nav_action`` or ``charge_action``
  naming a target point by ``index`` without coordinates gets the point's pose (A-22: ``x``,
  ``y``, ``theta`` are the goal; ``map``/``path``/``index`` are echoed), and the fields the
  server writes itself (``id``, ``state``, ``current_location`` ...) are dropped, so a client
  may send back an object it read.
* Outbound (:func:`render`): an engine snapshot becomes the vendor's task object (§2.3): ``id``,
  ``name``, ``loop_flag`` (always, A-12), ``state``, ``sub_tasks``, ``progress`` (0-1, A-10),
  ``current_task`` (``null`` before start), ``loop_count``, and ``control_type`` with its
  parameters on every control node of a behavior tree only. Actions carry ``id``, ``type``,
  ``state``, ``result``, ``progress`` and their parameters as given (§2.4); a ``nav_action``
  also ``current_location`` and ``current_distance`` (``-1`` when not running) and
  ``timeout`` 0. A plain task knows no ``FAIL`` (A-9: ``FAIL`` is a behavior-tree state), so
  its nodes show an engine ``FAIL`` as ``ERROR`` (``docs/decisions.md``).

Every task made here is owned by :data:`OWNER`; its ``kind`` says how it is shown and which
endpoint controls it (``stop_nav_task`` cancels a navigation task, not a loop).

GalileoStatus shows the target point a goal went to (``targetNumID``, ``chargeStatus``):
:class:`TaskTargets` follows the engine's ``task_changed`` events and remembers, for each goal
attempt of a Galileo task, the target its action names (:meth:`Context.remember_target`).
"""

from __future__ import annotations

import logging
from collections.abc import Iterator, Mapping
from typing import Any

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo.context import TARGET_WITHOUT_ID, Context, Target
from polynav.protocols.galileo.params import Params
from polynav.runtime import events

log = logging.getLogger(__name__)

OWNER = "galileo"

#: ``kind`` of the tasks made by ``POST /task`` (plain, and with a ``control_type``), by
#: ``POST /action`` without a task (A-13), by the goal and local-move endpoints, by the loop
#: endpoints, by ``go_charge`` and by the map transfers.
TASK = "task"
TREE = "behavior tree"
AUTO = "auto task"
NAVIGATION = "navigation"
LOOP = "loop"
CHARGE = "charge"
TRANSFER = "transfer"

#: Fields of a task or action object that the server writes: never parameters.
_SERVER_FIELDS = frozenset({"id", "state", "result", "progress", "current_task", "loop_count",
                            "token"})
#: The same for a ``nav_action`` (``timeout`` is a read-out there, not a parameter; §2.4).
_NAV_FIELDS = frozenset({"current_location", "current_distance", "timeout"})
#: Action types whose goal may be a target point (``map``, ``path``, ``index``).
_GOALS = ("nav_action", "charge_action")
_NOWHERE = {"x": -1, "y": -1, "theta": -1}
_ACTIVE = ("WORKING", "PAUSED")


# -- inbound -------------------------------------------------------------------------------


def action_spec(ctx: Context, body: Mapping[str, Any]) -> dict[str, Any]:
    """A Galileo action object as the engine's action form (module docstring).

    Raises:
        InvalidRequest: a mistyped target ``index``.
        NotFound: the target point's map, path or index does not exist.
    """
    kind = body.get("type")
    out = {k: v for k, v in body.items() if k not in _SERVER_FIELDS}
    if kind == "nav_action":
        out = {k: v for k, v in out.items() if k not in _NAV_FIELDS}
    if kind in _GOALS and "index" in out and "x" not in out and "y" not in out:
        index = out["index"]
        if isinstance(index, bool) or not isinstance(index, int):
            raise InvalidRequest("index", f"must be an integer, got {index!r}")
        map_name = out.get("map") or sessions.current_map(ctx)
        path = out.get("path") or sessions.current_path(ctx, str(map_name))
        pose = sessions.target_point(ctx, str(map_name), str(path), index).pose
        out.update(x=float(pose.x), y=float(pose.y), theta=float(pose.theta))
    return out


def tree_spec(ctx: Context, body: Mapping[str, Any]) -> dict[str, Any]:
    """A Galileo task or behavior tree (its root and every node under it) as the engine's
    tree form. Raises as :func:`action_spec`."""
    if "type" in body and "control_type" not in body:
        return action_spec(ctx, body)
    out = {k: v for k, v in body.items() if k not in _SERVER_FIELDS}
    children = out.get("sub_tasks")
    if isinstance(children, list):
        out["sub_tasks"] = [tree_spec(ctx, c) if isinstance(c, Mapping) else c
                            for c in children]
    return out


def body_of(params: Params) -> dict[str, Any]:
    """The request's fields, without the token (it may come in the body, §1)."""
    return {k: v for k, v in params.values.items() if k != "token"}


# -- outbound ------------------------------------------------------------------------------


def render(snapshot: Mapping[str, Any]) -> dict[str, Any]:
    """The Galileo task object of an engine snapshot (module docstring)."""
    tree = snapshot["kind"] == TREE
    body = render_node(snapshot["tree"], tree=tree)
    body.update(id=snapshot["id"], name=snapshot["name"])
    if "type" in snapshot["tree"]:  # an action alone at the root: shown as its task
        body = {"id": snapshot["id"], "name": snapshot["name"], "loop_flag": False,
                "state": body["state"], "sub_tasks": [body], "progress": body["progress"],
                "current_task": None if body["state"] == "WAITTING" else body,
                "loop_count": 0}
    return body


def render_node(node: Mapping[str, Any], *, tree: bool) -> dict[str, Any]:
    """One node of a snapshot and its subtree; ``tree``: it is part of a behavior tree."""
    if "type" in node:
        return _action(node, tree=tree)
    children = [render_node(c, tree=tree) for c in node["children"]]
    state = _state(node["state"], tree=tree)
    out: dict[str, Any] = {"id": node["id"], "name": node["name"],
                           "loop_flag": bool(node.get("loop_flag", False)), "state": state,
                           "sub_tasks": children, "progress": node["progress"],
                           "current_task": _current(state, children),
                           "loop_count": int(node.get("loop_count", 0))}
    if tree:
        out["control_type"] = node["kind"]
        out.update({k: v for k, v in node.items() if k not in _NODE_KEYS})
    return out


_NODE_KEYS = frozenset({"id", "name", "kind", "state", "result", "progress", "children",
                        "loop_flag", "loop_count"})


def _state(state: str, *, tree: bool) -> str:
    return "ERROR" if state == "FAIL" and not tree else state


def _current(state: str, children: list[dict[str, Any]]) -> dict[str, Any] | None:
    """The child running (or next to run); once ended without success, the child where it
    stopped; ``None`` before the start and after success."""
    if state in ("WAITTING", "COMPLETE"):
        return None
    for child in children:
        if child["state"] in _ACTIVE:
            return child
    wanted = ("WAITTING",) if state in _ACTIVE else ("ERROR", "FAIL", "CANCELLED")
    return next((c for c in children if c["state"] in wanted), None)


def _action(node: Mapping[str, Any], *, tree: bool) -> dict[str, Any]:
    out: dict[str, Any] = {**node["params"], "id": node["id"], "type": node["type"],
                           "state": _state(node["state"], tree=tree), "result": node["result"],
                           "progress": node["progress"]}
    if node["type"] == "nav_action":
        distance = node.get("distance_left")
        out.update(current_location=node.get("location") or dict(_NOWHERE),
                   current_distance=-1 if distance is None else float(distance), timeout=0)
    return out


def leaves(snapshot: Mapping[str, Any]) -> Iterator[Mapping[str, Any]]:
    """The action nodes of a snapshot, depth first."""
    stack = [snapshot["tree"]]
    while stack:
        node = stack.pop()
        if "type" in node:
            yield node
        stack.extend(reversed(node.get("children", [])))


# -- making and controlling ------------------------------------------------------------------


def create(ctx: Context, spec: Mapping[str, Any], *, kind: str, name: str | None = None,
           start: bool = False, temporary: bool = False) -> dict[str, Any]:
    """A Galileo task of ``spec`` (engine tree form) in the engine; its snapshot.

    Raises:
        InvalidRequest: anything wrong in ``spec`` (nothing is made).
    """
    targets(ctx)  # following task changes from before the task's first goal
    snapshot = ctx.runtime.tasks.create(spec, name=name, owner=OWNER, kind=kind,
                                        temporary=temporary, start=start)
    remember_targets(ctx, snapshot)
    return snapshot


def run(ctx: Context, name: str, actions: list[dict[str, Any]], *, kind: str,
        loop_flag: bool = False) -> dict[str, Any]:
    """Make a plain task of ``actions`` and start it at once (pre-empting the running task);
    its task object.

    Raises:
        InvalidRequest: a bad action (nothing is made).
        Conflict: the first action could not start (the task is kept, ended, and the reason
            is answered, as the endpoints that start tasks always did).
    """
    snapshot = create(ctx, {"name": name, "loop_flag": loop_flag, "sub_tasks": actions},
                      kind=kind, start=True)
    if snapshot["state"] in ("ERROR", "FAIL"):
        reasons = [n["result"] for n in leaves(snapshot) if n["result"]]
        raise Conflict(reasons[0] if reasons else "the task could not start")
    return render(snapshot)


def running(ctx: Context, kind: str | None = None) -> dict[str, Any] | None:
    """The snapshot of the running (or paused) Galileo task of ``kind``, if that is what the
    robot runs."""
    snapshot = ctx.runtime.tasks.running()
    if snapshot is None or snapshot["owner"] != OWNER:
        return None
    return snapshot if kind is None or snapshot["kind"] == kind else None


def last(ctx: Context, kind: str) -> dict[str, Any] | None:
    """The snapshot of the newest Galileo task of ``kind``."""
    found = ctx.runtime.tasks.list(owner=OWNER, kind=kind)
    return found[-1] if found else None


def cancel_running(ctx: Context, kind: str) -> dict[str, Any] | None:
    """Cancel the running Galileo task of ``kind``; its task object, ``None`` if none ran."""
    snapshot = running(ctx, kind)
    if snapshot is None:
        return None
    return render(ctx.runtime.tasks.cancel(snapshot["id"]))


# -- GalileoStatus targets -------------------------------------------------------------------


def target_of(node: Mapping[str, Any]) -> Target:
    """The Galileo target a goal action names: its target point (map, path, index), the
    charge pile for a ``charge_action``, else none (``targetNumID`` -2)."""
    params = node["params"]
    if node["type"] == "charge_action":
        return Target(sessions.CHARGE_PILE, params.get("map"))
    index = params.get("index")
    if node["type"] == "nav_action" and isinstance(index, int) and not isinstance(index, bool):
        return Target(index, params.get("map"), params.get("path"))
    return Target(TARGET_WITHOUT_ID)


def remember_targets(ctx: Context, snapshot: Mapping[str, Any]) -> None:
    """Remember the target of every goal attempt the task's actions started."""
    for node in leaves(snapshot):
        attempt = node.get("attempt_id")
        if isinstance(attempt, int):
            ctx.remember_target(attempt, target_of(node))


class TaskTargets:
    """The runtime's ``task_changed`` events, turned into remembered targets on demand."""

    def __init__(self, ctx: Context) -> None:
        self._ctx = ctx
        self._subscription = ctx.runtime.bus.subscribe(maxlen=10_000)

    def close(self) -> None:
        self._ctx.runtime.bus.unsubscribe(self._subscription)

    def update(self) -> None:
        """Remember the targets of the goals started since the last update."""
        started: set[str] = set()
        for event in self._subscription.get_nowait():
            if (isinstance(event, events.TaskChanged) and event.owner == OWNER
                    and event.node_kind == "action" and event.state == "WORKING"):
                started.add(event.task_id)
        for task_id in started:
            try:
                remember_targets(self._ctx, self._ctx.runtime.tasks.get(task_id))
            except NotFound:
                log.debug("galileo: task %s was forgotten before its targets were read",
                          task_id)


def targets(ctx: Context) -> TaskTargets:
    return ctx.state("galileo.task_targets", lambda: TaskTargets(ctx))
