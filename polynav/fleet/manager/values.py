"""What the fleet manager is configured with and what it hands out: its timings and limits,
the events it keeps for the API, the robots as it knows them, and the site it reads points
from."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol

from polynav.errors import ConfigError
from polynav.fleet import messages as m
from polynav.fleet.manager.dispatch import DispatchConfig
from polynav.site import Point

_KEY = "fleet.manager."


class SitePoints(Protocol):
    """The site's named points (:class:`polynav.store.SiteStore`)."""

    def point(self, map_name: str, name: str) -> Point: ...


@dataclass(frozen=True, slots=True)
class FleetManagerConfig:
    """The fleet manager's timings [s of site time] and limits.

    Attributes:
        resend_after: an order no state has confirmed within this is sent again.
        max_sends: an order sent this many times and still not confirmed counts as a failed
            attempt (the robot does not hear the fleet).
        max_attempts: a mission is claimed by robots at most this many times, then fails.
        dispatch_period: how often orders are re-sent and, after a change of the queue or a
            robot freed, the queue is dispatched.
        max_dispatch: at most this many missions are dispatched in one tick; the rest of the
            queue goes at the next tick (a full queue meeting a fleet of free robots, at
            start-up, went out as a thousand orders at once, answered a second late).
        lost_grace: a mission requeued because its robot was lost (its last will) goes to
            another robot only this long after, unless the robot comes back without it sooner:
            a restarted broker delivers every robot's will while the robots drive on, and
            they reconnect (with backoff) within seconds, still doing their missions.
        queue_poll_period: how often the queue is dispatched otherwise.
        dispatch: how robots are weighed.
        events_kept: how many events the manager keeps for the API.
    """

    resend_after: float = 5.0
    max_sends: int = 5
    max_attempts: int = 3
    dispatch_period: float = 0.5
    max_dispatch: int = 10
    lost_grace: float = 15.0
    queue_poll_period: float = 2.0
    dispatch: DispatchConfig = field(default_factory=DispatchConfig)
    events_kept: int = 1000

    def __post_init__(self) -> None:
        for name in ("resend_after", "dispatch_period", "queue_poll_period"):
            value = getattr(self, name)
            if not value > 0.0:
                raise ConfigError(_KEY + name, f"must be > 0, got {value}")
        for name in ("max_sends", "max_attempts", "events_kept", "max_dispatch"):
            value = getattr(self, name)
            if value < 1:
                raise ConfigError(_KEY + name, f"must be >= 1, got {value}")
        if not self.lost_grace >= 0.0:
            raise ConfigError(_KEY + "lost_grace", f"must be >= 0, got {self.lost_grace}")


@dataclass(frozen=True, slots=True)
class FleetEvent:
    """Something that happened in the fleet: ``kind`` (``"mission.done"``,
    ``"robot.connection"``...) at site time ``at`` [s], numbered by ``seq`` (from 1)."""

    seq: int
    at: float
    kind: str
    detail: Mapping[str, Any]


@dataclass(frozen=True, slots=True)
class RobotView:
    """A robot as the fleet manager knows it.

    Attributes:
        serial: its serial number.
        connection: its last ``connection`` state (``"ONLINE"``, ``"OFFLINE"``,
            ``"CONNECTIONBROKEN"``).
        state: its last state message, None before the first.
        state_at: when that state was read [s].
        mission: the mission it is doing for this manager, if any.
        order_id: that mission's order.
    """

    serial: str
    connection: str
    state: m.State | None
    state_at: float | None
    mission: str | None
    order_id: str | None
