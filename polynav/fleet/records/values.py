"""The fleet's records as values: missions, orders and audit entries (leases are
:class:`polynav.leases.book.Lease`, the same value the in-memory lease book hands out).

Times are seconds on the site's clock, as everywhere in the fleet layer: the records never read
a clock of their own, so simulated fleets and real ones store the same numbers.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any


class MissionState(enum.Enum):
    """Where a mission is in its life: queued, then active on one robot, then done or failed.
    A requeued mission goes back to queued, keeping its place by when it was created; one
    cancelled (queued or active) is cancelled for good."""

    QUEUED = "queued"
    ACTIVE = "active"
    DONE = "done"
    FAILED = "failed"
    CANCELLED = "cancelled"


@dataclass(frozen=True, slots=True)
class Mission:
    """Work for one robot: ``stops`` (a point, or points in order, on any floor) to go through.

    Attributes:
        mission_id: unique in the records (the caller's, or a random one).
        state: see :class:`MissionState`.
        stops: the stops as JSON objects, in order (each names at least its ``point``).
        robot: the robot doing it while active (and the one that did it once finished); None
            while queued.
        created: when it was added [s]; the queue is served oldest first.
        updated: when its state last changed [s].
        attempts: how many times a robot has claimed it (a mission requeued after a robot's
            last will has more than one).
    """

    mission_id: str
    state: MissionState
    stops: tuple[Mapping[str, Any], ...]
    robot: str | None
    created: float
    updated: float
    attempts: int


class OrderState(enum.Enum):
    """An order update sent to a robot: confirmed once a state from the robot names it (or a
    later update of the same order); superseded once a later update is sent before that."""

    SENT = "sent"
    CONFIRMED = "confirmed"
    SUPERSEDED = "superseded"


@dataclass(frozen=True, slots=True)
class Order:
    """One order update sent to a robot (VDA 5050: ``orderId`` with its ``orderUpdateId``).

    Attributes:
        order_id, update_id: the order and its update.
        robot: the robot it was sent to.
        mission: the mission it carries out, if any.
        state: see :class:`OrderState`.
        sent_at: when it was last sent [s] (re-sending moves it).
        confirmed_at: when a state confirmed it [s], None before.
        sends: how many times it was sent.
    """

    order_id: str
    update_id: int
    robot: str
    mission: str | None
    state: OrderState
    sent_at: float
    confirmed_at: float | None
    sends: int


@dataclass(frozen=True, slots=True)
class AuditEntry:
    """One state change in the records.

    Attributes:
        entry_id: increasing in the order the changes were made within one fleet manager (two
            managers' entries may interleave out of commit order: order by ``at`` across them).
        at: the site time of the change [s].
        actor: the fleet manager that made it (:attr:`FleetRecords.name`).
        what: what changed, e.g. ``"lease.granted"``, ``"mission.claimed"``.
        detail: the change's particulars (ids, robot, times) as a JSON object.
    """

    entry_id: int
    at: float
    actor: str
    what: str
    detail: Mapping[str, Any]
