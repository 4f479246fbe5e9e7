"""Yunji replies in the vendor's own terms (§2.2, §3.3)."""

from __future__ import annotations

import enum
from dataclasses import dataclass

from polynav.protocols.yunji.codec import MISSING


class Status(str, enum.Enum):
    """The ``status`` of a response (§2.2)."""

    OK = "OK"
    INVALID_REQUEST = "INVALID_REQUEST"
    REQUEST_DENIED = "REQUEST_DENIED"
    UNKNOWN_ERROR = "UNKNOWN_ERROR"
    GOAL_CAN_NOT_BE_REACHED = "GOAL_CAN_NOT_BE_REACHED"


class MoveStatus(str, enum.Enum):
    """``robot_status.move_status`` (§3.3)."""

    IDLE = "idle"
    RUNNING = "running"
    SUCCEEDED = "succeeded"
    FAILED = "failed"
    CANCELED = "canceled"


class MarkerType(enum.IntEnum):
    """Marker ``type`` / ``key`` values the spec names (§3.5.1); custom types are > 1000."""

    GENERAL = 0
    FRONT_DESK = 1
    LIFT_OUTSIDE = 3
    LIFT_INSIDE = 4
    GATE = 7
    CHARGING_PILE = 11
    CUSTOM = 1000


@dataclass(frozen=True, slots=True)
class StreamRequest:
    """A ``/api/request_data`` subscription change for the requesting connection (§3.9).

    Attributes:
        topic: ``robot_status`` or ``robot_velocity``.
        frequency: callbacks per simulated second [Hz].
        on: ``False`` for the deprecated ``switch=off`` (stop that topic).
    """

    topic: str
    frequency: float
    on: bool = True


@dataclass(frozen=True, slots=True)
class Reply:
    """What a handler answers; the server adds ``type``, ``command`` and ``uuid``.

    Attributes:
        status: the result code.
        error_message: ``""`` on success, else why.
        results: the interface's data, or :data:`~polynav.protocols.yunji.codec.MISSING` for
            none (``None`` is sent as ``null``).
        task_id: the task id of a started ``/api/move``.
        stream: a subscription the server is to start or stop on this connection.
    """

    status: Status = Status.OK
    error_message: str = ""
    results: object = MISSING
    task_id: str | None = None
    stream: StreamRequest | None = None


@dataclass(frozen=True, slots=True)
class Notification:
    """A ``type: notification`` packet for every client (§2.4, §3.10)."""

    code: str
    level: str
    description: str
    data: dict[str, object]
