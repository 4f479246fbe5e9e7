"""Light VDA 5050 vehicles: they follow their orders kinematically, for loading a fleet and broker.

A :class:`KinematicVehicle` speaks the same VDA 5050 as a polynav robot (orders checked whole by
:mod:`polynav.fleet.order_check` and rejected with the standard's errors, order updates
stitched on, instant actions with their action states, state on every event and at least every
``state_period``, visualization every ``visualization_period``), but has no sensors, no
localization and no navigation stack: it drives in straight lines from node to node at
``speed``, turned to face its way, and changes floors through a lift as a fixed wait
(``lift_wait``) at the lift nearest to it on the floor it leaves (``lifts``: where each map's
lift cars stand), coming out at the same place on the next floor (the shafts coincide). It asks
for no zones and no lift leases, and sees no one: it is the *light mode* of the fleet
benchmark, named as such in its output, for loading the master control and the broker with
many more vehicles than full robots allow (hundreds per process).

Many vehicles may share one connection (:class:`~polynav.fleet.shared_client.SharedClient`);
they then have no last will of their own.
"""

from __future__ import annotations

import dataclasses
import logging
import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass

from polynav.errors import ConfigError
from polynav.fleet import messages as m
from polynav.fleet.interface import Transport
from polynav.fleet.order_check import Verdict, check_order
from polynav.fleet.order_progress import OrderProgress, order_progress

log = logging.getLogger(__name__)

ACTION_STATES_KEPT = 20


@dataclass(frozen=True, slots=True)
class KinematicConfig:
    """How the light vehicles move and report.

    Attributes:
        speed: driving speed [m/s] (the robot profile's cruise speed).
        lift_wait: a change of floor takes this long [s].
        lifts: per map, the (x, y) where its lift cars stand; a vehicle changing floors drives
            to the nearest; a map with none changes floors where the vehicle stands.
        state_period: the longest between two states [s] (VDA 5050: at most 30).
        visualization_period: between two visualization messages [s]; None for none.
    """

    speed: float = 1.0
    lift_wait: float = 30.0
    lifts: dict[str, tuple[tuple[float, float], ...]] = dataclasses.field(default_factory=dict)
    state_period: float = 30.0
    visualization_period: float | None = 1.0

    def __post_init__(self) -> None:
        if not self.speed > 0.0:
            raise ConfigError("kinematic.speed", "must be > 0")
        if self.lift_wait < 0.0:
            raise ConfigError("kinematic.lift_wait", "must be >= 0")
        if not 0.0 < self.state_period <= 30.0:
            raise ConfigError("kinematic.state_period", "must be in (0, 30] s")
        if self.visualization_period is not None and self.visualization_period <= 0.0:
            raise ConfigError("kinematic.visualization_period", "must be > 0")


@dataclass(slots=True)
class _Leg:
    """Drive to (x, y) on ``map_id``; then wait ``wait`` [s] and be on ``then_map``; reaching it
    passes node ``node_index`` of the order if set."""

    x: float
    y: float
    map_id: str
    node_index: int | None = None
    wait: float = 0.0
    then_map: str | None = None


@dataclass(slots=True)
class _Run:
    order: m.Order
    next_index: int = 1
    failed: str | None = None

    @property
    def remaining(self) -> tuple[m.Node, ...]:
        return self.order.nodes[self.next_index:]

    @property
    def last_node(self) -> m.Node:
        return self.order.nodes[self.next_index - 1]


class KinematicVehicle:
    """One light vehicle (see the module docstring).

    Args:
        serial_number: its serial number, the fourth level of its topics.
        transport: where orders and instant actions come from and the state goes.
        config: speed, lifts, periods.
        start: where it stands at first.
        maps: the maps it may be sent to.
        headers: stamps its messages' headers (version, manufacturer, site clock).
        now: site time [s] it starts at.
        on_factsheet_request: publishes its factsheet; None fails the action.
        phase: in [0, 1): where in their periods this vehicle's periodic state and
            visualization fall, so that many vehicles started together do not all publish
            (and their readers all decode) in the same instant.
    """

    def __init__(self, serial_number: str, transport: Transport, config: KinematicConfig, *,
                 start: m.AgvPosition, maps: frozenset[str], headers: m.Headers,
                 now: float = 0.0,
                 on_factsheet_request: Callable[[], None] | None = None,
                 phase: float = 0.0) -> None:
        self.serial_number = serial_number
        self.config = config
        self._transport = transport
        self._headers = headers
        self._maps = maps
        self._orders = transport.subscribe(self._topic(m.Order))
        self._actions = transport.subscribe(self._topic(m.InstantActions))
        self.x, self.y, self.theta, self.map_id = start.x, start.y, start.theta, start.map_id
        self._moving = 0.0  # the speed of the last move [m/s]
        self._legs: deque[_Leg] = deque()
        self._waited = 0.0
        self._run: _Run | None = None
        self._paused = False
        self._errors: list[m.ErrorEntry] = []
        self._action_states: deque[m.ActionState] = deque(maxlen=ACTION_STATES_KEPT)
        self._on_factsheet_request = on_factsheet_request
        self._last = now
        self._dirty = True
        self._next_state = now
        self._phase = phase if 0.0 < phase < 1.0 else 1.0
        period = config.visualization_period
        self._next_visualization = now + (phase * period if period is not None else 0.0)
        self.distance = 0.0

    def _topic(self, kind: type | str) -> str:
        return m.topic(self.serial_number, kind, self._headers.manufacturer)

    # -- reads ---------------------------------------------------------------------------------

    @property
    def position(self) -> m.AgvPosition:
        return m.AgvPosition(self.x, self.y, self.theta, self.map_id, True, 1.0)

    @property
    def busy(self) -> bool:
        """Released nodes are left to drive to."""
        run = self._run
        return run is not None and run.failed is None and any(n.released for n in run.remaining)

    def state(self) -> m.State:
        """The state as the next state message says it."""
        run = self._run
        progress = (order_progress(run.order, run.next_index, failed=run.failed is not None)
                    if run is not None else OrderProgress())
        return m.State(
            header=self._headers.stamp(self.serial_number, m.State),
            order_id=progress.order_id,
            order_update_id=progress.order_update_id,
            last_node_id=progress.last_node_id,
            last_node_sequence_id=progress.last_node_sequence_id,
            node_states=progress.node_states,
            edge_states=progress.edge_states,
            driving=self._moving > 0.0,
            operating_mode="AUTOMATIC",
            battery_state=m.BatteryState(100.0, False),
            paused=self._paused,
            agv_position=self.position,
            velocity=m.Velocity(self._moving, 0.0, 0.0),
            errors=tuple(self._errors),
            action_states=tuple(self._action_states),
            navigation_state=("paused" if self._paused else "active" if self.busy else "idle"),
        )

    # -- the tick ------------------------------------------------------------------------------

    def tick(self, now: float) -> None:
        """Read orders and instant actions, move to ``now`` [s of site time], report."""
        for actions in self._actions.drain():
            if isinstance(actions, m.InstantActions):
                for action in actions.actions:
                    self._instant_action(action)
            else:
                self._refused(actions)
        for order in self._orders.drain():
            if isinstance(order, m.Order):
                self._take(order)
            else:
                self._refused(order)
        was_moving = self._moving > 0.0
        self._move(max(0.0, now - self._last))
        self._last = now
        if (self._moving > 0.0) != was_moving:
            self._dirty = True
        if self._dirty or now >= self._next_state:
            self.publish_state(now)
        period = self.config.visualization_period
        if period is not None and now >= self._next_visualization:
            self._transport.publish(self._topic(m.Visualization), m.Visualization(
                self._headers.stamp(self.serial_number, m.Visualization), self.position,
                m.Velocity(self._moving, 0.0, 0.0)))
            self._next_visualization = now + period

    def publish_state(self, now: float) -> None:
        """Publish the state now; the next is due ``state_period`` later."""
        self._transport.publish(self._topic(m.State), self.state())
        self._next_state = now + self.config.state_period * self._phase
        self._phase = 1.0
        self._dirty = False

    # -- orders --------------------------------------------------------------------------------

    def _take(self, order: m.Order) -> None:
        run = self._run
        check = check_order(
            order, current=run.order if run is not None else None,
            current_active=self.busy,
            last_node=((run.last_node.node_id, run.last_node.sequence_id)
                       if run is not None else None),
            here=self.position, maps=self._maps)
        if check.verdict is Verdict.IGNORE:
            return
        if check.verdict is Verdict.REJECT:
            assert check.error is not None
            self._report(check.error)
            return
        self._errors = []
        if check.verdict is Verdict.TAKE_UPDATE:
            assert run is not None
            first = order.nodes[0]
            k = next(i for i, n in enumerate(run.order.nodes)
                     if (n.node_id, n.sequence_id) == (first.node_id, first.sequence_id))
            run.order = dataclasses.replace(order, nodes=run.order.nodes[:k] + order.nodes,
                                            edges=run.order.edges[:k] + order.edges)
            run.failed = None
        else:
            self._run = run = _Run(order)
        self._plan(run)
        self._dirty = True

    def _plan(self, run: _Run) -> None:
        """The legs from where the vehicle is through the order's released nodes left."""
        self._legs.clear()
        self._waited = 0.0
        map_id = self.map_id
        x, y = self.x, self.y
        for index in range(run.next_index, len(run.order.nodes)):
            node = run.order.nodes[index]
            if not node.released:
                break
            p = node.node_position
            assert p is not None  # check_order rejects a node without a position
            if p.map_id != map_id:
                lx, ly = self._nearest_lift(map_id, x, y)
                self._legs.append(_Leg(lx, ly, map_id, wait=self.config.lift_wait,
                                       then_map=p.map_id))
                map_id, x, y = p.map_id, lx, ly
            self._legs.append(_Leg(p.x, p.y, p.map_id, node_index=index))
            x, y = p.x, p.y

    def _nearest_lift(self, map_id: str, x: float, y: float) -> tuple[float, float]:
        stops = self.config.lifts.get(map_id, ())
        if not stops:
            return x, y
        return min(stops, key=lambda s: math.hypot(s[0] - x, s[1] - y))

    def _move(self, dt: float) -> None:
        """Move ``dt`` [s] along the legs; then it drives if a leg's end is still ahead."""
        run = self._run
        if self._paused or run is None or run.failed is not None:
            self._moving = 0.0
            return
        self._advance(run, dt)
        ahead = self._legs[0] if self._legs else None
        self._moving = self.config.speed if ahead is not None and math.hypot(
            ahead.x - self.x, ahead.y - self.y) > 1e-9 else 0.0

    def _advance(self, run: _Run, dt: float) -> None:
        budget = dt
        while budget > 1e-9 and self._legs:
            leg = self._legs[0]
            dx, dy = leg.x - self.x, leg.y - self.y
            gap = math.hypot(dx, dy)
            if gap > 1e-9:
                step = min(gap, self.config.speed * budget)
                self.theta = math.atan2(dy, dx)
                self.x += dx / gap * step
                self.y += dy / gap * step
                self.distance += step
                budget -= step / self.config.speed
                if step < gap:
                    return
            if self._waited < leg.wait:  # in the lift
                used = min(budget, leg.wait - self._waited)
                self._waited += used
                budget -= used
                if self._waited < leg.wait - 1e-9:
                    return
            self._legs.popleft()
            self._waited = 0.0
            if leg.then_map is not None:
                self.map_id = leg.then_map
                self._dirty = True
            if leg.node_index is not None:
                run.next_index = leg.node_index + 1
                self._dirty = True

    # -- instant actions -----------------------------------------------------------------------

    def _instant_action(self, action: m.Action) -> None:
        try:
            result = self._carry_out(action)
            status = m.ActionStatus.FINISHED
        except _ActionFailed as exc:
            result, status = str(exc), m.ActionStatus.FAILED
        self._action_states.append(m.ActionState(action.action_id, status, action.action_type,
                                                 result))
        self._dirty = True

    def _carry_out(self, action: m.Action) -> str | None:
        kind = action.action_type
        run = self._run
        if kind == m.ActionType.CANCEL_ORDER.value:
            if run is None or not self.busy:
                self._report(m.ErrorEntry("noOrderToCancel", "WARNING",
                                          "cancelOrder with no order running",
                                          (m.ErrorReference("actionId", action.action_id),)))
                raise _ActionFailed("no order to cancel")
            self._legs.clear()
            self._fail(run, "canceled")
            return None
        if kind == m.ActionType.START_PAUSE.value:
            self._paused = True
            return None
        if kind == m.ActionType.STOP_PAUSE.value:
            self._paused = False
            return None
        if kind == m.ActionType.STATE_REQUEST.value:
            return None
        if kind == m.ActionType.FACTSHEET_REQUEST.value:
            if self._on_factsheet_request is None:
                raise _ActionFailed("no factsheet on this transport")
            self._on_factsheet_request()
            return None
        if kind == m.ActionType.INIT_POSITION.value:
            return self._init_position(action)
        if kind in (m.ActionType.START_CHARGING.value, m.ActionType.STOP_CHARGING.value):
            raise _ActionFailed("a kinematic vehicle has no charger contact")
        raise _ActionFailed(f"instant action {kind!r} is not supported")

    def _init_position(self, action: m.Action) -> str:
        values = [action.parameter(k) for k in ("x", "y", "theta")]
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            raise _ActionFailed("initPosition needs numbers x, y and theta")
        map_id = action.parameter("mapId")
        if map_id is not None and (not isinstance(map_id, str) or map_id not in self._maps):
            raise _ActionFailed(f"initPosition: unknown mapId {map_id!r}")
        if self.busy:
            raise _ActionFailed("initPosition while an order runs")
        x, y, theta = (float(v) for v in values)  # type: ignore[arg-type]
        self.x, self.y, self.theta = x, y, theta
        self.map_id = map_id or self.map_id
        return f"at ({x:.2f}, {y:.2f}, {theta:.2f}) on {self.map_id}"

    def _fail(self, run: _Run, why: str) -> None:
        run.failed = why
        refs: tuple[m.ErrorReference, ...] = (m.ErrorReference("orderId", run.order.order_id),)
        self._errors = [e for e in self._errors if e.error_type != "orderFailed"]
        self._errors.append(m.ErrorEntry("orderFailed", "WARNING", why, refs))
        self._dirty = True

    def _refused(self, rejected: m.Received) -> None:
        assert isinstance(rejected, m.Rejected)
        refs = [m.ErrorReference("topic", rejected.kind)]
        if rejected.header_id is not None:
            refs.append(m.ErrorReference("headerId", str(rejected.header_id)))
        if rejected.order_id is not None:
            refs.append(m.ErrorReference("orderId", rejected.order_id))
        self._report(m.ErrorEntry("validationError", "WARNING", rejected.reason, tuple(refs)))

    def _report(self, error: m.ErrorEntry) -> None:
        log.info("%s: %s: %s", self.serial_number, error.error_type, error.error_description)
        self._errors = [e for e in self._errors if e.error_type != "orderFailed"] + [error]
        del self._errors[:-5]
        self._dirty = True


class _ActionFailed(Exception):
    """An instant action that cannot be carried out; its message is the action's result."""
