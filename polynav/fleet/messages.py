"""The messages between the fleet and its robots: VDA 5050 (2.0.0 and 2.1.0).

VDA 5050 (the VDA/VDMA interface between AGVs and a master control) has the fleet send *orders*
(a graph of nodes and edges to drive through) and *instant actions* (cancel, pause, ...) to a
vehicle, and the vehicle publish its *state* (order progress, position, battery, errors, action
states), its *connection* state, its *factsheet* and a *visualization* stream. Every message on
those six topics carries the standard's header (:class:`Header`) and is checked against the
official JSON schema of its version when it is encoded and when it is decoded
(:mod:`polynav.fleet.codec`).

Version 3.0 adds *zone requests*, answered with a grant and a ``leaseExpiry``, which is how
polynav reserves narrow passages and lifts (:mod:`polynav.leases.book`). 2.x has no topic for
them, so they travel on polynav's own topics (``zoneRequest``, ``zoneResponse``) beside the
standard ones, with a short header of their own (docs/fleet.md, docs/decisions.md).

Field names here are snake_case; the codec writes VDA's camelCase JSON, leaving out fields that
are None (the schemas allow no nulls). The state carries four polynav fields besides the
standard's (``floor``, ``navigationState``, ``waitingFor``, ``zones``); the schemas allow extra
properties, and a master that does not know them ignores them.
"""

from __future__ import annotations

import datetime as dt
import enum
import itertools
from collections.abc import Callable
from dataclasses import dataclass, field

INTERFACE = "uagv"
"""The first level of every VDA 5050 topic."""

MAJOR = "v2"
"""The topic's major-version level for VDA 5050 2.x."""

DEFAULT_MANUFACTURER = "polynav"
DEFAULT_VERSION = "2.0.0"


@dataclass(frozen=True, slots=True)
class Header:
    """VDA 5050's header (§6.4): ``header_id`` counts up per topic and sender; ``timestamp`` is
    ISO 8601 UTC with milliseconds; ``version`` is the protocol version (``"2.0.0"``)."""

    header_id: int
    timestamp: str
    version: str
    manufacturer: str
    serial_number: str


class BlockingType(enum.Enum):
    NONE = "NONE"
    SOFT = "SOFT"
    HARD = "HARD"


@dataclass(frozen=True, slots=True)
class ActionParameter:
    key: str
    value: object


@dataclass(frozen=True, slots=True)
class Action:
    """An action (on a node, an edge, or instant). ``action_type`` is a string: an order may
    name actions polynav does not know, which it then rejects by name."""

    action_id: str
    action_type: str
    blocking_type: BlockingType = BlockingType.NONE
    action_parameters: tuple[ActionParameter, ...] = ()
    action_description: str | None = None

    def parameter(self, key: str) -> object:
        """The value of parameter ``key``, None if absent."""
        for p in self.action_parameters:
            if p.key == key:
                return p.value
        return None


class ActionType(enum.Enum):
    """The instant actions a polynav vehicle carries out (VDA 5050 §6.8 predefined actions)."""

    CANCEL_ORDER = "cancelOrder"
    START_PAUSE = "startPause"
    STOP_PAUSE = "stopPause"
    INIT_POSITION = "initPosition"
    STATE_REQUEST = "stateRequest"
    FACTSHEET_REQUEST = "factsheetRequest"
    START_CHARGING = "startCharging"
    STOP_CHARGING = "stopCharging"


@dataclass(frozen=True, slots=True)
class NodePosition:
    """Where a node is: x, y [m] and theta [rad, optional] on map ``map_id``."""

    x: float
    y: float
    theta: float | None
    map_id: str
    allowed_deviation_x_y: float | None = None


@dataclass(frozen=True, slots=True)
class Node:
    """One stop of an order. ``node_id`` is the site's point name when the node is a point."""

    node_id: str
    sequence_id: int
    node_position: NodePosition | None = None
    released: bool = True
    actions: tuple[Action, ...] = ()


@dataclass(frozen=True, slots=True)
class Edge:
    """The way from one node to the next; polynav plans its own path along it."""

    edge_id: str
    sequence_id: int
    start_node_id: str
    end_node_id: str
    released: bool = True
    actions: tuple[Action, ...] = ()
    max_speed: float | None = None


@dataclass(frozen=True, slots=True)
class Order:
    """Drive through ``nodes`` along ``edges`` (VDA 5050 §6.6); nodes and edges with
    ``released`` False are the horizon, planned but not yet to be driven."""

    header: Header
    order_id: str
    order_update_id: int
    nodes: tuple[Node, ...]
    edges: tuple[Edge, ...] = ()
    zone_set_id: str | None = None


@dataclass(frozen=True, slots=True)
class InstantActions:
    header: Header
    actions: tuple[Action, ...]


class ConnectionState(enum.Enum):
    ONLINE = "ONLINE"
    OFFLINE = "OFFLINE"
    CONNECTIONBROKEN = "CONNECTIONBROKEN"


@dataclass(frozen=True, slots=True)
class Connection:
    """The vehicle's link to the broker (§6.14): retained, QoS 1, CONNECTIONBROKEN as its will."""

    header: Header
    connection_state: ConnectionState


class ZoneRequestType(enum.Enum):
    """ACCESS asks for (or renews) a zone; RELEASE gives it back or leaves its queue."""

    ACCESS = "ACCESS"
    RELEASE = "RELEASE"


@dataclass(frozen=True, slots=True)
class ZoneRequest:
    """A robot asks for a zone (a narrow passage, a lift) for ``duration`` [s] (VDA 5050 3.0).

    ``flow`` (a polynav extension) is the way the robot goes through the zone, e.g. ``"E"``:
    robots going the same way may share it (:mod:`polynav.leases.book`); None asks for it alone.
    ``sent_at`` (a polynav extension) is the robot's site time [s] when it asked: the answer's
    ``lease_expiry`` is then on the robot's clock, whatever the fleet manager's (a ``polynav
    fleet`` started at another moment than the robots' ``polynav run``).
    """

    header_id: int
    serial_number: str
    request_id: str
    zone_id: str
    request_type: ZoneRequestType
    duration: float = 30.0
    flow: str | None = None
    sent_at: float | None = None


class GrantType(enum.Enum):
    """The fleet's answer to a zone request (VDA 5050 3.0 ``grantType``, plus EXPIRED)."""

    GRANTED = "GRANTED"
    QUEUED = "QUEUED"
    REVOKED = "REVOKED"
    REJECTED = "REJECTED"
    EXPIRED = "EXPIRED"
    RELEASED = "RELEASED"


@dataclass(frozen=True, slots=True)
class ZoneResponse:
    """The fleet's answer: granted until ``lease_expiry`` [s of site time], queued, or not.

    ``queue_position`` (polynav's addition, JSON ``queuePosition``) is a QUEUED robot's place in
    line, 0 next; the fleet sends QUEUED again whenever it changes.
    """

    header_id: int
    serial_number: str
    request_id: str
    zone_id: str
    grant_type: GrantType
    lease_expiry: float | None = None
    queue_position: int | None = None


@dataclass(frozen=True, slots=True)
class AgvPosition:
    """The robot's pose on ``map_id``; ``localization_score`` in [0, 1]."""

    x: float
    y: float
    theta: float
    map_id: str
    position_initialized: bool
    localization_score: float | None = None


@dataclass(frozen=True, slots=True)
class Velocity:
    """The robot's velocity in its own frame: vx, vy [m/s], omega [rad/s]."""

    vx: float
    vy: float
    omega: float


@dataclass(frozen=True, slots=True)
class NodeState:
    node_id: str
    sequence_id: int
    released: bool
    node_position: NodePosition | None = None


@dataclass(frozen=True, slots=True)
class EdgeState:
    edge_id: str
    sequence_id: int
    released: bool


class ActionStatus(enum.Enum):
    WAITING = "WAITING"
    INITIALIZING = "INITIALIZING"
    RUNNING = "RUNNING"
    FINISHED = "FINISHED"
    FAILED = "FAILED"


@dataclass(frozen=True, slots=True)
class ActionState:
    action_id: str
    action_status: ActionStatus
    action_type: str | None = None
    result_description: str | None = None


@dataclass(frozen=True, slots=True)
class BatteryState:
    """``battery_charge`` in percent."""

    battery_charge: float
    charging: bool


@dataclass(frozen=True, slots=True)
class ErrorReference:
    reference_key: str
    reference_value: str


@dataclass(frozen=True, slots=True)
class ErrorEntry:
    """An error the robot reports (VDA 5050 ``errors``): ``error_level`` WARNING or FATAL;
    ``error_type`` one of the standard's (``validationError``, ``noRouteError``,
    ``orderUpdateError``...) or polynav's ``orderFailed`` (an accepted order that could not be
    driven to its end)."""

    error_type: str
    error_level: str
    error_description: str = ""
    error_references: tuple[ErrorReference, ...] = ()


@dataclass(frozen=True, slots=True)
class SafetyState:
    e_stop: str = "NONE"
    field_violation: bool = False


@dataclass(frozen=True, slots=True)
class State:
    """The vehicle's state (VDA 5050 §6.10).

    ``node_states`` and ``edge_states`` are the order's nodes and edges not yet passed; an order
    is done when they are empty and the robot no longer drives. ``waiting_for`` names the zone
    the robot is waiting for, if any; it, ``floor``, ``navigation_state`` and ``zones`` are
    polynav's additions (shown by ``GET /api/fleet``).
    """

    header: Header
    order_id: str
    order_update_id: int
    last_node_id: str
    last_node_sequence_id: int
    node_states: tuple[NodeState, ...]
    edge_states: tuple[EdgeState, ...]
    driving: bool
    operating_mode: str
    battery_state: BatteryState
    paused: bool = False
    agv_position: AgvPosition | None = None
    velocity: Velocity | None = None
    errors: tuple[ErrorEntry, ...] = ()
    action_states: tuple[ActionState, ...] = ()
    safety_state: SafetyState = field(default_factory=SafetyState)
    new_base_request: bool | None = None
    floor: str | None = None
    navigation_state: str = "idle"
    waiting_for: str | None = None
    zones: tuple[str, ...] = ()

    @property
    def serial_number(self) -> str:
        return self.header.serial_number


@dataclass(frozen=True, slots=True)
class Visualization:
    """Position and velocity at a higher rate than the state (§6.15)."""

    header: Header
    agv_position: AgvPosition | None = None
    velocity: Velocity | None = None


Message = (Order | InstantActions | ZoneRequest | ZoneResponse | State | Connection
           | Visualization)

TOPICS: dict[type, str] = {
    Order: "order",
    InstantActions: "instantActions",
    ZoneRequest: "zoneRequest",
    ZoneResponse: "zoneResponse",
    State: "state",
    Connection: "connection",
    Visualization: "visualization",
}
"""The topic's last level for each message type: ``uagv/v2/<manufacturer>/<serial>/<topic>``."""


def topic(serial_number: str, kind: type | str,
          manufacturer: str = DEFAULT_MANUFACTURER) -> str:
    """The topic of a message of ``kind`` (a message type, or a topic name such as
    ``"factsheet"``) for vehicle ``serial_number`` of ``manufacturer``."""
    name = kind if isinstance(kind, str) else TOPICS[kind]
    return f"{INTERFACE}/{MAJOR}/{manufacturer}/{serial_number}/{name}"


@dataclass(frozen=True, slots=True)
class Rejected:
    """A message that arrived but cannot be used: not JSON, breaking its schema, or of a
    version polynav does not speak. Inboxes hand it over in place of the message, so the
    vehicle can report it (``validationError``) and the fleet can log it.

    ``header_id`` and ``order_id`` are what could be read of the message, for the report."""

    kind: str
    field: str
    reason: str
    header_id: int | None = None
    order_id: str | None = None


Received = Message | Rejected
"""What an inbox delivers."""


def iso_timestamp(moment: dt.datetime) -> str:
    """``moment`` as VDA 5050 writes time: ISO 8601 in UTC with milliseconds and a ``Z``."""
    utc = moment.astimezone(dt.UTC)
    return utc.strftime("%Y-%m-%dT%H:%M:%S.") + f"{utc.microsecond // 1000:03d}Z"


class Headers:
    """Stamps the headers of one sender's messages: ``header_id`` counts up per topic (§6.4),
    the timestamp is site time ``clock()`` [s] from ``epoch`` (the UTC moment site time 0
    stands for; simulated robots so stamp their simulated time onto the calendar).

    Args:
        version: the VDA 5050 version spoken, ``"2.0.0"`` or ``"2.1.0"``.
        manufacturer: the vehicles' manufacturer.
        clock: site time [s].
        epoch: the UTC moment of site time 0; by default, now minus ``clock()``.
    """

    def __init__(self, version: str, manufacturer: str, clock: Callable[[], float],
                 epoch: dt.datetime | None = None) -> None:
        self.version = version
        self.manufacturer = manufacturer
        self._clock = clock
        self.epoch = epoch or dt.datetime.now(dt.UTC) - dt.timedelta(seconds=clock())
        self._counters: dict[tuple[str, str], itertools.count[int]] = {}

    def stamp(self, serial_number: str, kind: type | str) -> Header:
        """The next header for a message of ``kind`` about vehicle ``serial_number``."""
        name = kind if isinstance(kind, str) else TOPICS[kind]
        counter = self._counters.setdefault((serial_number, name), itertools.count(0))
        moment = self.epoch + dt.timedelta(seconds=self._clock())
        return Header(next(counter), iso_timestamp(moment), self.version, self.manufacturer,
                      serial_number)
