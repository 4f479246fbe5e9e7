"""Whether a vehicle takes an order: VDA 5050's rejections, each with the standard's error."""

from __future__ import annotations

import dataclasses

import pytest

from polynav.fleet import messages as m
from polynav.fleet.order_check import Check, Verdict, check_order

HERE = m.AgvPosition(1.0, 1.0, 0.0, "floor1", True, 0.9)
MAPS = frozenset({"floor1", "floor2"})


def order(*points: tuple[str, float, float, str], order_id: str = "o1", update: int = 0,
          released: int | None = None) -> m.Order:
    cut = len(points) if released is None else released
    nodes = tuple(m.Node(name, 2 * k, m.NodePosition(x, y, 0.0, map_id), released=k < cut)
                  for k, (name, x, y, map_id) in enumerate(points))
    edges = tuple(m.Edge(f"{a.node_id}-{b.node_id}", a.sequence_id + 1, a.node_id, b.node_id,
                         released=b.released) for a, b in zip(nodes, nodes[1:], strict=False))
    header = m.Header(1, "2026-11-28T11:40:03.120Z", "2.1.0", "polynav", "r1")
    return m.Order(header, order_id, update, nodes, edges)


START = ("start", 1.2, 1.0, "floor1")
A = ("a", 5.0, 1.0, "floor1")
B = ("b", 9.0, 1.0, "floor1")


def check(new: m.Order, current: m.Order | None = None, *, active: bool = False,
          last: tuple[str, int] | None = None, here: m.AgvPosition | None = HERE) -> Check:
    return check_order(new, current=current, current_active=active, last_node=last, here=here,
                       maps=MAPS)


def test_an_order_starting_at_the_vehicle_is_taken() -> None:
    assert check(order(START, A, B)).verdict is Verdict.TAKE_NEW


@pytest.mark.parametrize(("new", "kind", "words"), [
    (order(("far", 4.0, 1.0, "floor1"), A), "noRouteError", "3.00 m from the vehicle"),
    (order(("up", 1.0, 1.0, "floor2"), A), "noRouteError", "on map 'floor2'"),
    (order(START, ("x", 1.0, 1.0, "floor9")), "validationError", "map 'floor9'"),
    (order(), "validationError", "at least one node"),
    (dataclasses.replace(order(START, A), edges=()), "validationError", "need 1 edges"),
    (order(START, A, B, released=0), "validationError", "released nodes must come first"),
])
def test_orders_it_cannot_drive_are_rejected_with_the_standards_error(
        new: m.Order, kind: str, words: str) -> None:
    result = check(new)
    assert result.verdict is Verdict.REJECT and result.error is not None
    assert result.error.error_type == kind and words in result.error.error_description
    assert m.ErrorReference("orderId", new.order_id) in result.error.error_references


def test_a_node_action_polynav_does_not_carry_out_is_a_validation_error() -> None:
    base = order(START, A)
    lift = dataclasses.replace(base.nodes[1], actions=(m.Action("p1", "pick"),))
    result = check(dataclasses.replace(base, nodes=(base.nodes[0], lift)))
    assert result.error is not None and result.error.error_type == "validationError"
    assert "'pick'" in result.error.error_description


def test_the_same_ids_again_are_ignored_a_stale_update_is_an_update_error() -> None:
    running = order(START, A, update=3)
    assert check(order(START, A, update=3), running, active=True,
                 last=("start", 0)).verdict is Verdict.IGNORE
    stale = check(order(START, A, update=2), running, active=True, last=("start", 0))
    assert stale.error is not None and stale.error.error_type == "orderUpdateError"


def test_an_update_is_stitched_at_the_last_released_node_only() -> None:
    running = order(START, A, B, released=2)  # base start, a; horizon b
    update = order(("a", 5.0, 1.0, "floor1"), B, update=1)
    update = dataclasses.replace(update, nodes=tuple(
        dataclasses.replace(n, sequence_id=n.sequence_id + 2) for n in update.nodes),
        edges=tuple(dataclasses.replace(e, sequence_id=e.sequence_id + 2)
                    for e in update.edges))
    assert check(update, running, active=True, last=("start", 0)).verdict is Verdict.TAKE_UPDATE
    elsewhere = order(START, B, update=1)
    result = check(elsewhere, running, active=True, last=("start", 0))
    assert result.error is not None and result.error.error_type == "orderUpdateError"


def test_a_new_order_while_one_is_driven_is_an_update_error() -> None:
    result = check(order(START, B, order_id="o2"), order(START, A), active=True,
                   last=("start", 0))
    assert result.error is not None and result.error.error_type == "orderUpdateError"
    assert check(order(START, B, order_id="o2"), order(START, A), active=False,
                 last=("a", 2)).verdict is Verdict.TAKE_NEW
