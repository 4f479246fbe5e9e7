"""The Galileo status vocabulary: the closed sets of GalileoStatus and ``/system/status``.

Spec galileo-http-a §1.5–1.6 (seed lines 345, 428–490), values exactly as documented.
"""

from __future__ import annotations

import enum


class SystemState(enum.Enum):
    """``GET /system/status`` ``status``."""

    MAPPING = "Mapping"
    NAVIGATING = "Navigating"
    BUSY = "Busy"
    FREE = "Free"


class NavStatus(enum.IntEnum):
    CLOSED = 0
    OPENED = 1


class VisualStatus(enum.IntEnum):
    OFF = -1
    UNINIT = 0
    TRACKING = 1
    LOST = 2


class MapStatus(enum.IntEnum):
    NOT_MAPPING = 0
    MAPPING = 1


class GbaStatus(enum.IntEnum):
    IDLE = 0
    OPTIMIZING = 1


class ChargeStatus(enum.IntEnum):
    FREE = 0
    CHARGING = 1
    CHARGED = 2
    FINDING = 3
    DOCKING = 4
    ERROR = 5


class LoopStatus(enum.IntEnum):
    OFF = 0
    LOOPING = 1


class TargetStatus(enum.IntEnum):
    INVALID = -1
    FREE = 0
    WORKING = 1
    PAUSED = 2
    ERROR = 3


class AngleGoalStatus(enum.IntEnum):
    INVALID = -1
    NOT_DONE = 0
    DONE = 1
    ERROR = 2


class TaskState(enum.Enum):
    """Task states, spelled as the vendor spells them (``WAITTING``)."""

    WAITTING = "WAITTING"
    WORKING = "WORKING"
    PAUSED = "PAUSED"
    CANCELLED = "CANCELLED"
    ERROR = "ERROR"
    COMPLETE = "COMPLETE"
