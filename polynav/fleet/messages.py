"""The messages between the fleet and its robots, in the shape of VDA 5050.

VDA 5050 (the VDA/VDMA interface between AGVs and a master control) has the fleet send *orders*
(a graph of nodes to drive through) and *instant actions* (cancel, pause) to a robot, and the
robot publish its *state* (order progress, position, battery, errors). Version 2.1 is what vendors
ship; version 3.0 adds *zone requests*, answered with a grant and a ``leaseExpiry``, which is how
polynav reserves narrow passages and lifts (:mod:`polynav.fleet.lease`).

Field names here are snake_case; :mod:`polynav.fleet.codec` writes VDA's camelCase JSON. What
polynav leaves out, and why, is in docs/decisions.md ("fleet"): orders carry nodes only (the robot
plans its own path between them, so edges carry nothing polynav uses), and zone requests and
their answers travel on their own topics rather than inside the state.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field


@dataclass(frozen=True, slots=True)
class NodePosition:
    """Where a node is: x, y [m] and theta [rad] on map ``map_id``."""

    x: float
    y: float
    theta: float
    map_id: str


@dataclass(frozen=True, slots=True)
class Node:
    """One stop of an order. ``node_id`` is the site's point name when the node is a point."""

    node_id: str
    sequence_id: int
    node_position: NodePosition
    released: bool = True


@dataclass(frozen=True, slots=True)
class Order:
    """Drive through ``nodes`` in order (VDA 5050 §6.6, nodes only)."""

    header_id: int
    serial_number: str
    order_id: str
    order_update_id: int
    nodes: tuple[Node, ...]


class ActionType(enum.Enum):
    """The instant actions a polynav robot carries out (VDA 5050 §6.8 predefined actions)."""

    CANCEL_ORDER = "cancelOrder"
    START_PAUSE = "startPause"
    STOP_PAUSE = "stopPause"


@dataclass(frozen=True, slots=True)
class Action:
    action_id: str
    action_type: ActionType


@dataclass(frozen=True, slots=True)
class InstantActions:
    header_id: int
    serial_number: str
    actions: tuple[Action, ...]


class ZoneRequestType(enum.Enum):
    """ACCESS asks for (or renews) a zone; RELEASE gives it back or leaves its queue."""

    ACCESS = "ACCESS"
    RELEASE = "RELEASE"


@dataclass(frozen=True, slots=True)
class ZoneRequest:
    """A robot asks for a zone (a narrow passage, a lift) for ``duration`` [s] (VDA 5050 3.0).

    ``flow`` (a polynav extension) is the way the robot goes through the zone, e.g. ``"E"``:
    robots going the same way may share it (:mod:`polynav.fleet.lease`); None asks for it alone.
    """

    header_id: int
    serial_number: str
    request_id: str
    zone_id: str
    request_type: ZoneRequestType
    duration: float = 30.0
    flow: str | None = None


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
    localization_score: float


@dataclass(frozen=True, slots=True)
class ErrorEntry:
    """An error the robot reports (VDA 5050 ``errors``): ``error_level`` WARNING or FATAL."""

    error_type: str
    error_level: str
    error_description: str = ""


@dataclass(frozen=True, slots=True)
class State:
    """The robot's state (VDA 5050 §6.10, the fields polynav fills).

    ``node_states`` are the ids of the order's nodes not yet reached; an order is done when it is
    empty and the robot no longer drives, and failed when ``errors`` holds an ``orderFailed``.
    ``waiting_for`` names the zone the robot is waiting for, if any (polynav's addition, shown
    by ``GET /api/fleet``).
    """

    header_id: int
    serial_number: str
    timestamp: float
    order_id: str
    order_update_id: int
    last_node_id: str
    node_states: tuple[str, ...]
    driving: bool
    paused: bool
    operating_mode: str
    agv_position: AgvPosition | None
    battery_charge: float
    errors: tuple[ErrorEntry, ...] = ()
    floor: str | None = None
    navigation_state: str = "idle"
    waiting_for: str | None = None
    zones: tuple[str, ...] = field(default=())


Message = Order | InstantActions | ZoneRequest | ZoneResponse | State

TOPICS: dict[type, str] = {
    Order: "order",
    InstantActions: "instantActions",
    ZoneRequest: "zoneRequest",
    ZoneResponse: "zoneResponse",
    State: "state",
}
"""The VDA 5050 topic suffix of each message type: ``uagv/v2/<manufacturer>/<serial>/<topic>``."""


def topic(serial_number: str, kind: type) -> str:
    """The MQTT-style topic of a message of ``kind`` for robot ``serial_number``."""
    return f"uagv/v2/polynav/{serial_number}/{TOPICS[kind]}"
