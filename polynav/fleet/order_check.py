"""Whether a vehicle takes an order (VDA 5050 §6.6): the checks before anything moves.

Pure: the order, what the vehicle runs now, where it stands and which maps it knows in; a
verdict out. An order the vehicle cannot take is rejected as a whole, with the standard's error
type, and the vehicle keeps what it was doing:

- ``validationError``: no nodes, more nodes than :data:`MAX_NODES`, an id longer than
  :data:`MAX_ID`, a node without a position or with one beyond :data:`MAX_COORDINATE`, a map
  the site does not have,
  edges that do not join the nodes in order, sequence ids out of order, an action polynav does
  not carry out, a base that does not start with released nodes;
- ``noRouteError``: the first node of a new order is not where the vehicle stands (a new order
  starts at the vehicle, §6.6.1: more than its allowed deviation away, or on another map);
- ``orderUpdateError``: an update older than the one running (a stale update), an update
  whose first node is not the running order's last released node (it cannot be stitched on),
  or a new order while the last is still being driven.

An order re-sent with the orderId and orderUpdateId of the one running is neither taken nor
rejected: it is ignored (the fleet may repeat itself, e.g. after a reconnection).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from polynav.fleet import messages as m

DEFAULT_DEVIATION = 1.0
"""How far [m] the vehicle may stand from a new order's first node when the node gives no
``allowedDeviationXY``."""

NODE_ACTIONS: frozenset[str] = frozenset()
"""The actions polynav carries out on a node or an edge of an order: none yet (its orders are
drives); an order with any other is rejected rather than driven without it."""


MAX_NODES = 1000
"""The most nodes an order may have (the factsheet's ``maxArrayLens`` ``order.nodes``): a
building's longest drive has a few dozen; an order of thousands is an error or an attack, and
is refused before the robot plans anything for it."""

MAX_ID = 200
"""The longest orderId, nodeId or edgeId [characters] (the factsheet's ``maxStringLens.idLen``):
ids go back to the fleet in every state, so one of 300 kB would bloat each of them."""

MAX_COORDINATE = 100_000.0
"""The largest |x|, |y| [m] a node may have: no site is 100 km across, and a coordinate of
1e308 must be refused here rather than reach the planner's grid arithmetic."""


class Verdict(enum.Enum):
    TAKE_NEW = "new"
    TAKE_UPDATE = "update"
    IGNORE = "ignore"
    REJECT = "reject"


@dataclass(frozen=True, slots=True)
class Check:
    """The verdict; ``error`` says why when it is REJECT."""

    verdict: Verdict
    error: m.ErrorEntry | None = None


def check_order(order: m.Order, *, current: m.Order | None, current_active: bool,
                last_node: tuple[str, int] | None, here: m.AgvPosition | None,
                maps: frozenset[str]) -> Check:
    """Whether to take ``order`` (see the module docstring).

    Args:
        order: what arrived.
        current: the order the vehicle has (running or ended), None before its first.
        current_active: whether ``current`` is still being driven (released nodes left).
        last_node: the (nodeId, sequenceId) the vehicle last passed in ``current``.
        here: where the vehicle stands, None if it does not know.
        maps: the maps the vehicle can drive on.
    """
    refs = (m.ErrorReference("orderId", order.order_id),
            m.ErrorReference("orderUpdateId", str(order.order_update_id)))
    if current is not None and order.order_id == current.order_id:
        if order.order_update_id == current.order_update_id:
            return Check(Verdict.IGNORE)
        if order.order_update_id < current.order_update_id:
            return _reject("orderUpdateError", refs,
                           f"update {order.order_update_id} of order {order.order_id} is older "
                           f"than the running update {current.order_update_id}")
    problem = _shape_problem(order, maps)
    if problem is not None:
        return _reject("validationError", refs, problem)
    first = order.nodes[0]
    if current is not None and order.order_id == current.order_id:
        if last_node is None or current_active and not _stitches(first, current):
            return _reject("orderUpdateError", refs,
                           f"update {order.order_update_id} starts at node {first.node_id} "
                           f"(sequence {first.sequence_id}), not at the last released node of "
                           "the running order")
        if not current_active and (first.node_id, first.sequence_id) != last_node:
            return _reject("orderUpdateError", refs,
                           f"update {order.order_update_id} starts at node {first.node_id}, "
                           f"not at the node last passed ({last_node[0]})")
        return Check(Verdict.TAKE_UPDATE)
    if current_active:
        assert current is not None
        return _reject("orderUpdateError", refs,
                       f"order {current.order_id} is still being driven: cancel it first")
    far = _far_from(first, here)
    if far is not None:
        return _reject("noRouteError", refs + (m.ErrorReference("nodeId", first.node_id),), far)
    return Check(Verdict.TAKE_NEW)


def _reject(kind: str, refs: tuple[m.ErrorReference, ...], why: str) -> Check:
    return Check(Verdict.REJECT, m.ErrorEntry(kind, "WARNING", why, refs))


def _stitches(first: m.Node, current: m.Order) -> bool:
    released = [n for n in current.nodes if n.released]
    return bool(released) and (released[-1].node_id, released[-1].sequence_id) == (
        first.node_id, first.sequence_id)


def _shape_problem(order: m.Order, maps: frozenset[str]) -> str | None:
    if not order.nodes:
        return "an order needs at least one node"
    ids = [order.order_id, *(n.node_id for n in order.nodes), *(e.edge_id for e in order.edges)]
    if any(len(i) > MAX_ID for i in ids):
        return f"an id longer than {MAX_ID} characters"
    if len(order.nodes) > MAX_NODES:
        return f"{len(order.nodes)} nodes: polynav takes at most {MAX_NODES} in one order"
    for node in order.nodes:
        if node.node_position is None:
            return f"node {node.node_id} has no nodePosition: polynav needs where to go"
        position = node.node_position
        if not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE
                   for v in (position.x, position.y)) or (
                position.theta is not None and not math.isfinite(position.theta)):
            return (f"node {node.node_id}: position ({position.x:g}, {position.y:g}) is out of "
                    f"range (|x|, |y| <= {MAX_COORDINATE:g} m)")
        if node.node_position.map_id not in maps:
            return f"node {node.node_id}: map {node.node_position.map_id!r} is not on this site"
        for action in node.actions:
            if action.action_type not in NODE_ACTIONS:
                return f"node {node.node_id}: action {action.action_type!r} is not supported"
    for k, node in enumerate(order.nodes):
        if node.sequence_id != order.nodes[0].sequence_id + 2 * k:
            return (f"node {node.node_id}: sequenceId {node.sequence_id}, expected "
                    f"{order.nodes[0].sequence_id + 2 * k} (nodes even, edges between)")
    if len(order.edges) != len(order.nodes) - 1:
        return f"{len(order.nodes)} nodes need {len(order.nodes) - 1} edges, got {len(order.edges)}"
    for k, edge in enumerate(order.edges):
        a, b = order.nodes[k], order.nodes[k + 1]
        if (edge.start_node_id, edge.end_node_id, edge.sequence_id) != (
                a.node_id, b.node_id, a.sequence_id + 1):
            return (f"edge {edge.edge_id} must join {a.node_id} to {b.node_id} with sequenceId "
                    f"{a.sequence_id + 1}")
        for action in edge.actions:
            if action.action_type not in NODE_ACTIONS:
                return f"edge {edge.edge_id}: action {action.action_type!r} is not supported"
        if edge.released and not b.released:
            return f"edge {edge.edge_id} is released but its end node {b.node_id} is not"
    flags = [n.released for n in order.nodes]
    if not flags[0] or flags != sorted(flags, reverse=True):
        return "the released nodes must come first (the base), then the horizon"
    return None


def _far_from(first: m.Node, here: m.AgvPosition | None) -> str | None:
    position = first.node_position
    assert position is not None
    if here is None:
        return f"the vehicle does not know where it is, so it cannot start at {first.node_id}"
    if here.map_id != position.map_id:
        return (f"the first node {first.node_id} is on map {position.map_id!r}, the vehicle on "
                f"{here.map_id!r}")
    allowed = position.allowed_deviation_x_y or DEFAULT_DEVIATION
    distance = math.hypot(position.x - here.x, position.y - here.y)
    if distance > allowed:
        return (f"the first node {first.node_id} is {distance:.2f} m from the vehicle "
                f"(allowed {allowed:.2f} m)")
    return None
