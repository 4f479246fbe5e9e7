"""How far a vehicle is through its order, as its VDA 5050 state says it.

Both kinds of vehicle (a polynav robot's :class:`~polynav.fleet.agent.RobotAgent` and the light
:class:`~polynav.fleet.kinematic_vehicle.KinematicVehicle`) keep their order and the index of
the next node to reach; the order part of their state (§6.10: orderId, orderUpdateId,
lastNodeId, lastNodeSequenceId, nodeStates, edgeStates) follows from those alone, and is built
here once so the two cannot drift apart on what a master control reads as "done".

Rules: node 0 is where the vehicle stood when it took the order (passed at once); the nodes
from ``next_index`` on are left, each with the edge leading to it; a failed order lists no
nodes or edges (its error in ``errors`` says why); no order at all is the standard's empty
ids and sequence 0.
"""

from __future__ import annotations

from dataclasses import dataclass

from polynav.fleet import messages as m


@dataclass(frozen=True, slots=True)
class OrderProgress:
    """The order fields of a state message (VDA 5050 §6.10)."""

    order_id: str = ""
    order_update_id: int = 0
    last_node_id: str = ""
    last_node_sequence_id: int = 0
    node_states: tuple[m.NodeState, ...] = ()
    edge_states: tuple[m.EdgeState, ...] = ()


def order_progress(order: m.Order | None, next_index: int, *, failed: bool) -> OrderProgress:
    """The order part of the state of a vehicle running ``order``.

    Args:
        order: the order it runs or last ran (updates stitched on); None before any.
        next_index: the index in ``order.nodes`` of the next node to reach (>= 1).
        failed: the order failed or was cancelled: no node or edge is left to it.
    """
    if order is None:
        return OrderProgress()
    last = order.nodes[next_index - 1]
    nodes = () if failed else order.nodes[next_index:]
    edges = order.edges[next_index - 1:] if nodes else ()
    return OrderProgress(
        order_id=order.order_id,
        order_update_id=order.order_update_id,
        last_node_id=last.node_id,
        last_node_sequence_id=last.sequence_id,
        node_states=tuple(m.NodeState(n.node_id, n.sequence_id, n.released,
                                      with_theta(n.node_position)) for n in nodes),
        edge_states=tuple(m.EdgeState(e.edge_id, e.sequence_id, e.released) for e in edges),
    )


def with_theta(position: m.NodePosition | None) -> m.NodePosition | None:
    """A node's position as the state shows it: 2.0.0's node states require a theta (0 when
    the order left it free)."""
    if position is None or position.theta is not None:
        return position
    return m.NodePosition(position.x, position.y, 0.0, position.map_id)
