"""The robot agent: one per robot, between the fleet's messages and the robot's runtime.

The fleet never calls a robot (DESIGN §9); it sends messages, and the agent on the robot's side
turns them into runtime commands and reports back:

- an **order** (VDA 5050) becomes one goal per node, in order; the order is done when the last
  node is reached, failed (an ``orderFailed`` error in the state) when a goal fails;
- **instant actions** cancel the order, pause or resume it;
- the robot's **state** (order progress, pose, map and floor, battery, errors, the zones it holds
  or waits for) is published every ``state_period`` and at once when the order changes;
- the **traffic rule** (:mod:`polynav.fleet.traffic`) is kept here: a zone on the path ahead is
  asked for before the robot gets to it, the robot stops short of it until it is granted, holds
  the lease (renewed) while it is inside, and gives it back once it has left;
- the robot's **lift sessions** (:mod:`polynav.fleet.lift_sessions`) are asked for the same way,
  as leases on ``lift:<car>``.

The agent runs on the robot's loop, between physics steps (:meth:`RobotAgent.tick`), so its
commands to the runtime run at once and never wait.
"""

from __future__ import annotations

import itertools
import logging
from dataclasses import dataclass

from polynav.errors import PolynavError
from polynav.fleet import messages as m
from polynav.fleet.interface import Transport
from polynav.fleet.lift_sessions import FleetLiftSessions
from polynav.fleet.traffic import TrafficConfig, TrafficRule
from polynav.fleet.zones import ZoneMap
from polynav.runtime.config import Mode
from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)


@dataclass(slots=True)
class _OrderRun:
    order: m.Order
    next_index: int = 0
    attempt_id: int | None = None
    last_node_id: str = ""
    failed: str | None = None
    paused_by_fleet: bool = False

    @property
    def remaining(self) -> tuple[str, ...]:
        return tuple(n.node_id for n in self.order.nodes[self.next_index:])


class RobotAgent:
    """The fleet's side of one robot (see the module docstring).

    Args:
        serial_number: the robot's id in the fleet (VDA 5050 ``serialNumber``).
        runtime: the robot.
        transport: where the fleet's messages come from and the state goes.
        zones: the traffic zones of each map, by map name.
        traffic: the traffic rule's distances and timings.
        state_period: how often the state is published [s].
    """

    def __init__(
        self,
        serial_number: str,
        runtime: RobotRuntime,
        transport: Transport,
        zones: dict[str, ZoneMap],
        *,
        traffic: TrafficConfig | None = None,
        state_period: float = 1.0,
    ) -> None:
        self.serial_number = serial_number
        self.runtime = runtime
        self._transport = transport
        self._orders = transport.subscribe(m.topic(serial_number, m.Order))
        self._actions = transport.subscribe(m.topic(serial_number, m.InstantActions))
        self._responses = transport.subscribe(m.topic(serial_number, m.ZoneResponse))
        self.traffic = TrafficRule(serial_number, zones, traffic or TrafficConfig(),
                                   self._send_zone_request)
        # Lift sessions are leases on lift:<car> in the same book, asked for the same way.
        self.lift_sessions = FleetLiftSessions(serial_number, self._send_zone_request)
        runtime.use_lift_sessions(self.lift_sessions)
        self._state_period = state_period
        self._next_state = runtime.now()
        self._headers = itertools.count(1)
        self._run: _OrderRun | None = None
        self._last_order_id = ""
        self._last_update_id = 0
        self._state_dirty = True
        self._outcomes: dict[str, str] = {}

    def outcome_of(self, order_id: str) -> str | None:
        """How order ``order_id`` ended (``"succeeded"``, ``"failed: <why>"``), None until it
        has (or if this robot never had it)."""
        run = self._run
        if run is not None and run.order.order_id == order_id:
            return self.outcome
        return self._outcomes.get(order_id)

    @property
    def busy(self) -> bool:
        """Whether an order runs (not finished, not failed)."""
        run = self._run
        return run is not None and run.failed is None and bool(run.remaining)

    @property
    def outcome(self) -> str | None:
        """How the last order ended: ``"succeeded"``, ``"failed: <why>"``, or None while it
        runs (or before the first)."""
        run = self._run
        if run is None:
            return None
        if run.failed is not None:
            return f"failed: {run.failed}"
        return None if run.remaining else "succeeded"

    def tick(self, now: float) -> None:
        """Read the fleet's messages, follow the order and the traffic rule, report the state."""
        for response in self._responses.drain():
            assert isinstance(response, m.ZoneResponse)
            self.traffic.on_response(response)
            self.lift_sessions.on_response(response)
        for actions in self._actions.drain():
            assert isinstance(actions, m.InstantActions)
            for action in actions.actions:
                self._instant_action(action)
        for order in self._orders.drain():
            assert isinstance(order, m.Order)
            self._start_order(order)
        self._follow_order()
        self.traffic.tick(now, self.runtime)
        if self._state_dirty or now >= self._next_state:
            self._publish_state(now)

    # -- orders --------------------------------------------------------------------------------

    def _start_order(self, order: m.Order) -> None:
        previous = self._run
        if previous is not None:
            self._outcomes[previous.order.order_id] = self.outcome or "failed: replaced"
        if self.runtime.mode is not Mode.NAVIGATING:
            self._run = _OrderRun(order, failed="the robot is not navigating")
        elif not order.nodes:
            self._run = _OrderRun(order, failed="an order needs at least one node")
        else:
            self._run = _OrderRun(order)
            log.info("%s: order %s with %d nodes", self.serial_number, order.order_id,
                     len(order.nodes))
        self._last_order_id, self._last_update_id = order.order_id, order.order_update_id
        self.traffic.resume_goal(self.runtime)
        self._state_dirty = True

    def _instant_action(self, action: m.Action) -> None:
        run = self._run
        if run is None or not self.busy:
            return
        try:
            if action.action_type is m.ActionType.CANCEL_ORDER:
                self.traffic.resume_goal(self.runtime)
                self.runtime.cancel()
                run.failed = "canceled"
            elif action.action_type is m.ActionType.START_PAUSE and not run.paused_by_fleet:
                self.traffic.resume_goal(self.runtime)
                self.runtime.pause()
                run.paused_by_fleet = True
            elif action.action_type is m.ActionType.STOP_PAUSE and run.paused_by_fleet:
                self.runtime.resume()
                run.paused_by_fleet = False
        except PolynavError as exc:
            log.warning("%s: %s failed: %s", self.serial_number, action.action_type.value, exc)
        self._state_dirty = True

    def _follow_order(self) -> None:
        run = self._run
        if run is None or run.failed is not None or not run.remaining:
            return
        status = self.runtime.status()
        if run.attempt_id is not None and status.attempt_id == run.attempt_id:
            state = status.navigation_state
            if state == "succeeded":
                run.last_node_id = run.order.nodes[run.next_index].node_id
                run.next_index += 1
                run.attempt_id = None
                self._state_dirty = True
            elif state in ("failed", "canceled"):
                run.failed = f"node {run.order.nodes[run.next_index].node_id}: {state}" + (
                    f" ({status.reason})" if status.reason else "")
                log.warning("%s: order %s failed: %s", self.serial_number, run.order.order_id,
                            run.failed)
                self._state_dirty = True
                return
            else:
                return
        if run.attempt_id is None and run.remaining:
            node = run.order.nodes[run.next_index]
            try:
                run.attempt_id = self.runtime.go_to(point=node.node_id,
                                                    map_name=node.node_position.map_id)
            except PolynavError as exc:
                run.failed = f"node {node.node_id}: {exc}"
                log.warning("%s: order %s failed: %s", self.serial_number, run.order.order_id,
                            run.failed)
            self._state_dirty = True

    # -- state ---------------------------------------------------------------------------------

    def _publish_state(self, now: float) -> None:
        status = self.runtime.status()
        run = self._run
        errors: tuple[m.ErrorEntry, ...] = ()
        if run is not None and run.failed is not None:
            errors = (m.ErrorEntry("orderFailed", "WARNING", run.failed),)
        position = None
        if status.map is not None:
            position = m.AgvPosition(
                status.pose.x, status.pose.y, status.pose.theta, status.map,
                status.localization_state == "tracking", float(status.localization_quality))
        state = m.State(
            header_id=next(self._headers),
            serial_number=self.serial_number,
            timestamp=now,
            order_id=self._last_order_id,
            order_update_id=self._last_update_id,
            last_node_id=run.last_node_id if run is not None else "",
            node_states=run.remaining if run is not None and run.failed is None else (),
            driving=abs(status.linear) > 1e-3 or abs(status.angular) > 1e-3,
            paused=status.navigation_state == "paused",
            operating_mode="AUTOMATIC",
            agv_position=position,
            battery_charge=float(status.battery_percent),
            errors=errors,
            floor=status.floor,
            navigation_state=status.navigation_state,
            waiting_for=self.traffic.waiting_for,
            zones=self.traffic.held,
        )
        self._transport.publish(m.topic(self.serial_number, m.State), state)
        self._next_state = now + self._state_period
        self._state_dirty = False

    def _send_zone_request(self, request_id: str, zone_id: str,
                           request_type: m.ZoneRequestType, duration: float,
                           flow: str | None = None) -> None:
        self._transport.publish(
            m.topic(self.serial_number, m.ZoneRequest),
            m.ZoneRequest(next(self._headers), self.serial_number, request_id, zone_id,
                          request_type, duration, flow))
        self._state_dirty = True
