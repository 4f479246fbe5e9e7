"""A task tree from its JSON form, checked whole before anything is made.

The form is Galileo's (galileo-tasks-bt-ws §7.2), which the native API shares: a control node
is ``{"control_type": "...", "name": "...", <its parameters>, "sub_tasks": [...]}``, an action
``{"type": "<action type>", <its parameters>}``, and an object with ``name`` and ``sub_tasks``
but no ``control_type`` is a plain task: a sequence that loops with ``loop_flag``. The native
form may also name shared subtrees once, in ``nodes`` beside the root, and use a name in place of
a child (``"sub_tasks": ["go_to_dock", {...}]``); each use is a copy. A name that is not in
``nodes``, a subtree that contains itself, an unknown type, a wrong child count or a bad
parameter is an :class:`~polynav.errors.InvalidRequest` naming where, and nothing is made.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import polynav.tasks.actions  # noqa: F401  (registers every action type)
from polynav.errors import InvalidRequest
from polynav.tasks.action import ACTIONS, Action
from polynav.tasks.blackboard import check_key
from polynav.tasks.control import CONTROLS, Loop, Parallel, Sequence
from polynav.tasks.node import Node

MAX_NODES = 2000
MAX_DEPTH = 32


def build(spec: Mapping[str, Any], *, shared: Mapping[str, Any] | None = None) -> Node:
    """The tree ``spec`` describes (the module docstring).

    Raises:
        InvalidRequest: anything wrong in it, with where.
    """
    if shared is None:
        nodes = spec.get("nodes") if isinstance(spec, Mapping) else None
        if nodes is not None and not isinstance(nodes, Mapping):
            raise InvalidRequest("nodes", "must be an object of name: node")
        shared = nodes or {}
    for key in shared:
        check_key(key, "nodes")
    return _Builder(shared).node(spec, "root", 0, ())


class _Builder:
    def __init__(self, shared: Mapping[str, Any]) -> None:
        self.shared = shared
        self.count = 0

    def node(self, spec: object, where: str, depth: int, using: tuple[str, ...]) -> Node:
        if isinstance(spec, str):
            if spec not in self.shared:
                raise InvalidRequest(where, f"no node named {spec!r} in nodes")
            if spec in using:
                raise InvalidRequest(where, f"node {spec!r} contains itself: "
                                            f"{' -> '.join((*using, spec))}")
            return self.node(self.shared[spec], f"{where} ({spec})", depth, (*using, spec))
        if not isinstance(spec, Mapping):
            raise InvalidRequest(where, "a node is an object (or the name of one in nodes)")
        self.count += 1
        if self.count > MAX_NODES:
            raise InvalidRequest(where, f"a task holds at most {MAX_NODES} nodes")
        if depth > MAX_DEPTH:
            raise InvalidRequest(where, f"a task nests at most {MAX_DEPTH} levels")
        name = spec.get("name", "")
        if not isinstance(name, str):
            raise InvalidRequest(f"{where}.name", "must be a string")
        if "type" in spec and "control_type" not in spec:
            return self.action(spec, where, name)
        return self.control(spec, where, name, depth, using)

    def action(self, spec: Mapping[str, Any], where: str, name: str) -> Action:
        kind = spec["type"]
        cls = ACTIONS.get(kind) if isinstance(kind, str) else None
        if cls is None:
            raise InvalidRequest(f"{where}.type", f"unknown action type {kind!r}; known: "
                                                  f"{', '.join(sorted(ACTIONS))}")
        try:
            return cls(spec, name=name)
        except InvalidRequest as exc:
            raise InvalidRequest(f"{where} ({kind})", f"{exc.field}: {exc.reason}"
                                 ) from None

    def control(self, spec: Mapping[str, Any], where: str, name: str, depth: int,
                using: tuple[str, ...]) -> Node:
        kind = spec.get("control_type", "sequence")
        cls = CONTROLS.get(kind) if isinstance(kind, str) else None
        if cls is None:
            raise InvalidRequest(f"{where}.control_type", f"unknown control type {kind!r}; "
                                                          f"known: {', '.join(sorted(CONTROLS))}")
        raw = spec.get("sub_tasks", spec.get("children"))
        if not isinstance(raw, list):
            raise InvalidRequest(f"{where}.sub_tasks", "must be a list of nodes")
        children = [self.node(child, f"{where}.sub_tasks[{i}]", depth + 1, using)
                    for i, child in enumerate(raw)]
        try:
            if cls is Loop:
                return Loop(children, name=name,
                            target_loop_count=spec.get("target_loop_count", 0))
            if cls is Parallel:
                return Parallel(children, name=name, success_count=spec.get("success_count", 0))
            if cls is Sequence:
                loop = spec.get("loop_flag", False)
                if not isinstance(loop, bool):
                    raise InvalidRequest("loop_flag", "must be true or false")
                return Sequence(children, name=name, loop_flag=loop)
            return cls(children, name=name)
        except InvalidRequest as exc:
            raise InvalidRequest(f"{where} ({kind})", f"{exc.field}: {exc.reason}"
                                 ) from None
