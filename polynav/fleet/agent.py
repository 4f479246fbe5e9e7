"""The robot agent: one per robot, the VDA 5050 vehicle between the fleet and the robot's runtime.

The fleet never calls a robot (DESIGN §9); it sends messages, and the agent on the robot's side
turns them into runtime commands and reports back:

- an **order** (VDA 5050 §6.6) is checked whole first (:mod:`polynav.fleet.order_check`) and
  rejected with the standard's error in the state if it cannot be driven; taken, its first node is
  where the robot stands, and each further released node becomes one goal, in order (a node named
  after a site point on its map, within 0.5 m of it, is that point, lifts and chargers included;
  another node its position). The order is done when its last node is reached, failed (an
  ``orderFailed`` error in the state) when a goal fails. An update with the same orderId and a
  higher orderUpdateId is stitched on at the running order's last released node; a re-sent order
  (same ids) is ignored; a message that breaks its schema gets a ``validationError``;
- **instant actions** (§6.8: cancelOrder, startPause, stopPause, initPosition, stateRequest,
  factsheetRequest, startCharging, stopCharging) are carried out at once, each with its action
  state (FINISHED or FAILED with the reason) in the next state;
- the robot's **state** (§6.10: order progress, node and edge states, pose, velocity, battery,
  errors, action states) is published at once on every event (an order taken, rejected, a node
  passed, an action, a change of driving, paused, charging, map or e-stop) and otherwise every
  ``state_period``; **visualization** (pose and velocity) every ``visualization_period`` if set;
- the **traffic rule** (:mod:`polynav.fleet.traffic`) is kept here: a zone on the path ahead is
  asked for before the robot gets to it, the robot stops short of it until it is granted, holds
  the lease (renewed) while it is inside, and gives it back once it has left;
- the robot's **lift sessions** (:mod:`polynav.fleet.lift_sessions`) are asked for the same way,
  as leases on ``lift:<car>``, and so are the doors on its way (``door:<name>``,
  :mod:`polynav.runtime.door_passage`).

The agent runs on the robot's loop, between physics steps (:meth:`RobotAgent.tick`), so its
commands to the runtime run at once and never wait.
"""

from __future__ import annotations

import dataclasses
import datetime as dt
import logging
import math
import threading
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

from polynav.errors import PolynavError
from polynav.fleet import messages as m
from polynav.fleet.interface import Transport
from polynav.fleet.lift_sessions import FleetLiftSessions
from polynav.fleet.order_check import MAX_COORDINATE, Verdict, check_order
from polynav.fleet.order_progress import OrderProgress, order_progress
from polynav.fleet.traffic import TrafficConfig, TrafficRule
from polynav.fleet.zones import ZoneMap
from polynav.geometry import Pose2D
from polynav.runtime.config import Mode
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.runtime.status import StatusSnapshot

log = logging.getLogger(__name__)

POINT_MATCH = 0.5
"""How close [m] a node must be to the site's point of its name to be driven to as that point
(docked onto if a charger, through the lifts' routes as a named goal)."""

ACTION_STATES_KEPT = 20
"""How many instant actions' states the state lists (the latest)."""

OUTCOMES_KEPT = 1000
"""How many ended orders' outcomes the agent remembers (the latest), for :meth:`outcome_of`."""

ERROR_TEXT = 200
"""The longest an error's description or reference value in the state may be [characters]: a
bad message's 300 kB orderId, echoed in every state, would make each state too long for the
fleet to read (and the logs unreadable)."""


@runtime_checkable
class Reconnecting(Protocol):
    """A transport that can lose its broker and tell when it is back (the MQTT one)."""

    def add_reconnect_listener(self, listener: Callable[[], None]) -> None: ...


@dataclass(slots=True)
class _OrderRun:
    order: m.Order
    next_index: int = 1  # node 0 is where the robot stood when the order was taken
    attempt_id: int | None = None
    failed: str | None = None
    paused_by_fleet: bool = False

    @property
    def last_node(self) -> m.Node:
        return self.order.nodes[self.next_index - 1]

    @property
    def remaining(self) -> tuple[m.Node, ...]:
        return self.order.nodes[self.next_index:]

    @property
    def driving_on(self) -> bool:
        """Released nodes are left to drive to and nothing failed."""
        return self.failed is None and any(n.released for n in self.remaining)


class RobotAgent:
    """The fleet's side of one robot, a VDA 5050 vehicle (see the module docstring).

    Args:
        serial_number: the robot's id in the fleet (VDA 5050 ``serialNumber``).
        runtime: the robot.
        transport: where the fleet's messages come from and the state goes.
        zones: the traffic zones of each map, by map name.
        traffic: the traffic rule's distances and timings.
        state_period: the longest between two states [s] (VDA 5050: at most 30 s).
        visualization_period: how often the visualization is published [s]; None for never.
        version: the VDA 5050 version spoken (``"2.0.0"`` or ``"2.1.0"``).
        manufacturer: the robot's manufacturer, the third level of its topics.
        epoch: the UTC moment site time 0 stands for (headers' timestamps); now by default.
        on_factsheet_request: called for a factsheetRequest (publishes the factsheet); None
            fails the action (no factsheet on this transport).
        fleet_leases: whether polynav's fleet answers zone requests and lends lift cars; a
            vehicle under another master control (a lone robot on a broker) asks for none
            and rides lifts as a lone robot does.
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
        visualization_period: float | None = None,
        version: str = m.DEFAULT_VERSION,
        manufacturer: str = m.DEFAULT_MANUFACTURER,
        epoch: dt.datetime | None = None,
        on_factsheet_request: Callable[[], None] | None = None,
        fleet_leases: bool = True,
    ) -> None:
        self.serial_number = serial_number
        self.manufacturer = manufacturer
        self.runtime = runtime
        self._transport = transport
        self.headers = m.Headers(version, manufacturer, runtime.now, epoch)
        self._orders = transport.subscribe(self.topic(m.Order))
        self._actions = transport.subscribe(self.topic(m.InstantActions))
        self._responses = transport.subscribe(self.topic(m.ZoneResponse))
        self.traffic = TrafficRule(serial_number, zones if fleet_leases else {},
                                   traffic or TrafficConfig(), self._send_zone_request)
        # Lift sessions are leases on lift:<car> in the same book, asked for the same way.
        self.lift_sessions = FleetLiftSessions(serial_number, self._send_zone_request)
        # Doors on the robot's way are leases on door:<name>, the same way (several robots
        # through one door take turns).
        self.door_leases = FleetLiftSessions(serial_number, self._send_zone_request,
                                             kind="door")
        if fleet_leases:
            runtime.use_lift_sessions(self.lift_sessions)
            runtime.doors_rule.use_leases(self.door_leases)
        self._state_period = state_period
        self._visualization_period = visualization_period
        self._next_state = runtime.now()
        self._next_visualization = runtime.now()
        self._zone_headers = 0
        self._run: _OrderRun | None = None
        self._paused = False
        self._errors: list[m.ErrorEntry] = []
        self._action_states: deque[m.ActionState] = deque(maxlen=ACTION_STATES_KEPT)
        self._on_factsheet_request = on_factsheet_request
        self._state_dirty = True
        self._seen: tuple[object, ...] = ()
        self._outcomes: dict[str, str] = {}
        # Set from the transport's network thread when the broker is back; read on the tick.
        self._relinked = threading.Event()
        if isinstance(transport, Reconnecting):
            transport.add_reconnect_listener(self._relinked.set)

    def topic(self, kind: type | str) -> str:
        """This robot's topic for messages of ``kind``."""
        return m.topic(self.serial_number, kind, self.manufacturer)

    def outcome_of(self, order_id: str) -> str | None:
        """How order ``order_id`` ended (``"succeeded"``, ``"failed: <why>"``, a rejected
        order ``"failed: <why>"`` too), None until it has (or if this robot never had it)."""
        run = self._run
        if run is not None and run.order.order_id == order_id:
            return self.outcome
        return self._outcomes.get(order_id)

    @property
    def busy(self) -> bool:
        """Whether an order runs (released nodes left, not failed)."""
        return self._run is not None and self._run.driving_on

    @property
    def outcome(self) -> str | None:
        """How the last order ended: ``"succeeded"``, ``"failed: <why>"``, or None while it
        runs, waits for its horizon to be released (or before the first)."""
        run = self._run
        if run is None:
            return None
        if run.failed is not None:
            return f"failed: {run.failed}"
        return None if run.remaining else "succeeded"

    def tick(self, now: float) -> None:
        """Read the fleet's messages, follow the order and the traffic rule, report the state."""
        if self._relinked.is_set():
            # Back on the broker: what was published meanwhile (QoS 0) is lost, so the state
            # goes out at once and every zone asked for or held is asked for again.
            self._relinked.clear()
            log.info("%s: back on the broker; state and zone requests sent again",
                     self.serial_number)
            self._state_dirty = True
            self.traffic.resend()
            self.lift_sessions.resend()
            self.door_leases.resend()
        for response in self._responses.drain():
            if isinstance(response, m.ZoneResponse):
                self.traffic.on_response(response)
                self.lift_sessions.on_response(response)
                self.door_leases.on_response(response)
            else:
                log.warning("%s: a zone response not used: %s", self.serial_number, response)
        for actions in self._actions.drain():
            if isinstance(actions, m.InstantActions):
                for action in actions.actions:
                    self._instant_action(action)
            else:
                self._refused(actions)
        for order in self._orders.drain():
            if isinstance(order, m.Order):
                self._take_order(order)
            else:
                self._refused(order)
        self._follow_order()
        self.traffic.tick(now, self.runtime)
        status = self.runtime.status()
        # §6.10: a state also on a change of driving, paused, charging, the map or the e-stop.
        seen = (_driving(status), status.navigation_state == "paused", status.charging,
                status.map, status.estop_hardware or status.estop_software)
        if seen != self._seen:
            self._seen = seen
            self._state_dirty = True
        if self._state_dirty or now >= self._next_state:
            self.publish_state(now)
        if self._visualization_period is not None and now >= self._next_visualization:
            self._publish_visualization()
            self._next_visualization = now + self._visualization_period

    # -- orders --------------------------------------------------------------------------------

    def _refused(self, rejected: m.Received) -> None:
        """A message that broke its schema: a validationError in the state (§6.6.1)."""
        assert isinstance(rejected, m.Rejected)
        refs = [m.ErrorReference("topic", rejected.kind)]
        if rejected.header_id is not None:
            refs.append(m.ErrorReference("headerId", str(rejected.header_id)))
        if rejected.order_id is not None:
            refs.append(m.ErrorReference("orderId", rejected.order_id))
        self._report(m.ErrorEntry("validationError", "WARNING", rejected.reason, tuple(refs)))
        if rejected.order_id is not None and rejected.order_id not in self._outcomes:
            self._remember(rejected.order_id, f"failed: {_clip(rejected.reason)}")

    def _remember(self, order_id: str, outcome: str) -> None:
        """Keep how ``order_id`` ended, forgetting the oldest beyond :data:`OUTCOMES_KEPT`;
        an id too long for any master's order (a bad message's) is not kept."""
        if len(order_id) > ERROR_TEXT:
            return
        self._outcomes.pop(order_id, None)
        self._outcomes[order_id] = outcome
        while len(self._outcomes) > OUTCOMES_KEPT:
            del self._outcomes[next(iter(self._outcomes))]

    def _report(self, error: m.ErrorEntry) -> None:
        error = dataclasses.replace(
            error, error_description=_clip(error.error_description),
            error_references=tuple(dataclasses.replace(r, reference_value=_clip(
                r.reference_value)) for r in error.error_references))
        log.warning("%s: %s: %s", self.serial_number, error.error_type, error.error_description)
        self._errors = [e for e in self._errors if e.error_type != "orderFailed"] + [error]
        del self._errors[:-5]
        self._state_dirty = True

    def _take_order(self, order: m.Order) -> None:
        run = self._run
        status = self.runtime.status()
        here = self._position(status)
        maps = frozenset(n.node_position.map_id for n in order.nodes
                         if n.node_position is not None and self._has_map(n.node_position.map_id))
        check = check_order(
            order, current=run.order if run is not None else None,
            current_active=run is not None and run.driving_on,
            last_node=((run.last_node.node_id, run.last_node.sequence_id)
                       if run is not None else None), here=here, maps=maps)
        if check.verdict is Verdict.IGNORE:
            log.info("%s: order %s/%d again: ignored", self.serial_number, order.order_id,
                     order.order_update_id)
            return
        if check.verdict is Verdict.REJECT:
            assert check.error is not None
            self._report(check.error)
            if run is None or order.order_id != run.order.order_id:
                self._remember(order.order_id, f"failed: {check.error.error_description}")
            return
        if self.runtime.mode is not Mode.NAVIGATING:
            self._report(m.ErrorEntry("validationError", "WARNING",
                                      "the robot is not navigating (start navigation first)",
                                      (m.ErrorReference("orderId", order.order_id),)))
            self._remember(order.order_id, "failed: the robot is not navigating")
            return
        self._errors = []
        if check.verdict is Verdict.TAKE_UPDATE:
            assert run is not None
            # Stitch (§6.6.2): the update's first node is one of the running order's; what
            # came before it stays, what came after it (the old horizon) is replaced.
            first = order.nodes[0]
            k = next(i for i, n in enumerate(run.order.nodes)
                     if (n.node_id, n.sequence_id) == (first.node_id, first.sequence_id))
            run.order = dataclasses.replace(order, nodes=run.order.nodes[:k] + order.nodes,
                                            edges=run.order.edges[:k] + order.edges)
            run.failed = None
            log.info("%s: order %s updated (%d)", self.serial_number, order.order_id,
                     order.order_update_id)
        else:
            if run is not None:
                self._remember(run.order.order_id, self.outcome or "failed: replaced")
            self._run = _OrderRun(order)
            log.info("%s: order %s with %d nodes", self.serial_number, order.order_id,
                     len(order.nodes))
        self.traffic.resume_goal(self.runtime)
        self._state_dirty = True

    def _follow_order(self) -> None:
        run = self._run
        if run is None or not run.driving_on:
            return
        status = self.runtime.status()
        if run.attempt_id is not None and status.attempt_id == run.attempt_id:
            state = status.navigation_state
            if state == "succeeded":
                run.next_index += 1
                run.attempt_id = None
                self._state_dirty = True
            elif state in ("failed", "canceled"):
                self._fail(run, f"node {run.remaining[0].node_id}: {state}" + (
                    f" ({status.reason})" if status.reason else ""))
                return
            else:
                return
        if run.attempt_id is None and run.driving_on and not self._paused:
            node = run.remaining[0]
            position = node.node_position
            assert position is not None  # checked when the order was taken
            try:
                if self._is_point(node.node_id, position):
                    run.attempt_id = self.runtime.go_to(point=node.node_id,
                                                        map_name=position.map_id)
                else:
                    theta = position.theta if position.theta is not None else status.pose.theta
                    run.attempt_id = self.runtime.go_to(
                        pose=Pose2D(position.x, position.y, theta), map_name=position.map_id)
            except PolynavError as exc:
                kind = "noRouteError" if "route" in type(exc).__name__.lower() else "orderFailed"
                self._fail(run, f"node {node.node_id}: {exc}", kind)
            self._state_dirty = True

    def _has_map(self, name: str) -> bool:
        try:
            self.runtime.store.map_record(name)
        except PolynavError:
            return False
        return True

    def _is_point(self, name: str, position: m.NodePosition) -> bool:
        """Whether the node is the site's point ``name``: one of that name on its map within
        :data:`POINT_MATCH` of its position (the node's position is what the master means)."""
        try:
            point = self.runtime.store.point(position.map_id, name)
        except PolynavError:
            return False
        return math.hypot(point.pose.x - position.x, point.pose.y - position.y) <= POINT_MATCH

    def _fail(self, run: _OrderRun, why: str, kind: str = "orderFailed") -> None:
        run.failed = why
        log.warning("%s: order %s failed: %s", self.serial_number, run.order.order_id, why)
        refs: tuple[m.ErrorReference, ...] = (m.ErrorReference("orderId", run.order.order_id),)
        if run.remaining:
            refs += (m.ErrorReference("nodeId", run.remaining[0].node_id),)
        self._errors = [e for e in self._errors if e.error_type != "orderFailed"]
        if kind != "orderFailed":
            self._errors.append(m.ErrorEntry(kind, "WARNING", why, refs))
        self._errors.append(m.ErrorEntry("orderFailed", "WARNING", why, refs))
        self._state_dirty = True

    # -- instant actions -----------------------------------------------------------------------

    def _instant_action(self, action: m.Action) -> None:
        try:
            result = self._carry_out(action)
            status = m.ActionStatus.FINISHED
        except PolynavError as exc:
            result, status = str(exc), m.ActionStatus.FAILED
            log.warning("%s: %s failed: %s", self.serial_number, action.action_type, exc)
        self._action_states.append(m.ActionState(action.action_id, status, action.action_type,
                                                 result))
        self._state_dirty = True

    def _carry_out(self, action: m.Action) -> str | None:
        """Do ``action``; what it did, or raise why not."""
        kind = action.action_type
        run = self._run
        if kind == m.ActionType.CANCEL_ORDER.value:
            if run is None or not run.driving_on:
                self._report(m.ErrorEntry("noOrderToCancel", "WARNING",
                                          "cancelOrder with no order running",
                                          (m.ErrorReference("actionId", action.action_id),)))
                raise _ActionFailed("no order to cancel")
            self.traffic.resume_goal(self.runtime)
            if run.attempt_id is not None and self.runtime.status().attempt_id == run.attempt_id:
                self.runtime.cancel()
            self._fail(run, "canceled")
            return None
        if kind == m.ActionType.START_PAUSE.value:
            if not self._paused:
                self._paused = True
                if run is not None and run.attempt_id is not None and run.driving_on:
                    self.traffic.resume_goal(self.runtime)
                    self.runtime.pause()
                    run.paused_by_fleet = True
            return None
        if kind == m.ActionType.STOP_PAUSE.value:
            if self._paused:
                self._paused = False
                if run is not None and run.paused_by_fleet:
                    run.paused_by_fleet = False
                    self.runtime.resume()
            return None
        if kind == m.ActionType.STATE_REQUEST.value:
            self._state_dirty = True
            return None
        if kind == m.ActionType.FACTSHEET_REQUEST.value:
            if self._on_factsheet_request is None:
                raise _ActionFailed("no factsheet on this transport")
            self._on_factsheet_request()
            return None
        if kind == m.ActionType.INIT_POSITION.value:
            return self._init_position(action)
        if kind == m.ActionType.START_CHARGING.value:
            if not self.runtime.status().charging:
                raise _ActionFailed("not on a charger: send an order to a charger point (it "
                                    "docks and charges there)")
            return "charging"
        if kind == m.ActionType.STOP_CHARGING.value:
            if self.runtime.status().charging:
                raise _ActionFailed("on the charger: send an order elsewhere (it backs off "
                                    "the charger first)")
            return "not charging"
        raise _ActionFailed(f"instant action {kind!r} is not supported")

    def _init_position(self, action: m.Action) -> str:
        values = {k: action.parameter(k) for k in ("x", "y", "theta", "mapId")}
        x, y, theta, map_id = values["x"], values["y"], values["theta"], values["mapId"]
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (x, y, theta)):
            raise _ActionFailed("initPosition needs numbers x, y and theta")
        assert isinstance(x, (int, float)) and isinstance(y, (int, float))
        assert isinstance(theta, (int, float))
        if not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE for v in (x, y, theta)):
            raise _ActionFailed(f"initPosition out of range: |x|, |y|, |theta| must be <= "
                                f"{MAX_COORDINATE:g}")
        pose = Pose2D(float(x), float(y), float(theta))
        status = self.runtime.status()
        if map_id is None or map_id == status.map:
            self.runtime.set_initial_pose(pose)
        elif isinstance(map_id, str):
            self.runtime.start_navigation(map_id, pose=pose)
        else:
            raise _ActionFailed("initPosition's mapId must be a string")
        return f"at ({pose.x:.2f}, {pose.y:.2f}, {pose.theta:.2f}) on {map_id or status.map}"

    # -- state ---------------------------------------------------------------------------------

    @staticmethod
    def _position(status: StatusSnapshot) -> m.AgvPosition | None:
        if status.map is None:
            return None
        return m.AgvPosition(
            status.pose.x, status.pose.y, status.pose.theta, status.map,
            status.localization_state == "tracking",
            min(1.0, max(0.0, float(status.localization_quality))))

    def state(self) -> m.State:
        """The robot's state now, as the next state message would say it."""
        status = self.runtime.status()
        run = self._run
        progress = (order_progress(run.order, run.next_index, failed=run.failed is not None)
                    if run is not None else OrderProgress())
        return m.State(
            header=self.headers.stamp(self.serial_number, m.State),
            order_id=progress.order_id,
            order_update_id=progress.order_update_id,
            last_node_id=progress.last_node_id,
            last_node_sequence_id=progress.last_node_sequence_id,
            node_states=progress.node_states,
            edge_states=progress.edge_states,
            driving=_driving(status),
            operating_mode="AUTOMATIC",
            battery_state=m.BatteryState(float(status.battery_percent), status.charging),
            paused=self._paused or status.navigation_state == "paused",
            agv_position=self._position(status),
            velocity=m.Velocity(float(status.linear), 0.0, float(status.angular)),
            errors=tuple(self._errors),
            action_states=tuple(self._action_states),
            safety_state=m.SafetyState(
                "MANUAL" if status.estop_hardware else
                "REMOTE" if status.estop_software else "NONE", False),
            floor=status.floor,
            navigation_state=status.navigation_state,
            waiting_for=self.traffic.waiting_for,
            zones=self.traffic.held,
        )

    def publish_state(self, now: float) -> None:
        """Publish the state now; the next one is due ``state_period`` later."""
        self._transport.publish(self.topic(m.State), self.state())
        self._next_state = now + self._state_period
        self._state_dirty = False

    def _publish_visualization(self) -> None:
        status = self.runtime.status()
        self._transport.publish(self.topic(m.Visualization), m.Visualization(
            self.headers.stamp(self.serial_number, m.Visualization), self._position(status),
            m.Velocity(float(status.linear), 0.0, float(status.angular))))

    def _send_zone_request(self, request_id: str, zone_id: str,
                           request_type: m.ZoneRequestType, duration: float,
                           flow: str | None = None) -> None:
        self._zone_headers += 1
        self._transport.publish(
            self.topic(m.ZoneRequest),
            m.ZoneRequest(self._zone_headers, self.serial_number, request_id, zone_id,
                          request_type, duration, flow, sent_at=self.runtime.now()))
        self._state_dirty = True


def _clip(text: str) -> str:
    """``text``, cut to :data:`ERROR_TEXT` characters (saying how long it was)."""
    if len(text) <= ERROR_TEXT:
        return text
    return f"{text[:ERROR_TEXT]}... ({len(text)} characters)"


def _driving(status: StatusSnapshot) -> bool:
    return abs(status.linear) > 1e-3 or abs(status.angular) > 1e-3


class _ActionFailed(PolynavError):
    """An instant action that cannot be carried out; its message is the action's result."""
