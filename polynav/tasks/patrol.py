"""A patrol: rounds over named points, one navigation leg per point (a Yunji cruise).

The patrol only decides what comes next; the runtime starts each leg as a navigation goal and
reports how it ended. A failed leg is skipped: the robot goes on to the next point (vendors'
cruises do the same), and the patrol as a whole fails only when its very last leg fails.
``count`` rounds of every point, or ``FOREVER`` until canceled.
"""

from __future__ import annotations

import enum
import logging
from dataclasses import dataclass

from polynav.errors import InvalidRequest

log = logging.getLogger(__name__)

FOREVER = -1


class PatrolState(enum.Enum):
    RUNNING = "running"
    SUCCEEDED = "succeeded"
    FAILED = "failed"
    CANCELED = "canceled"


@dataclass(frozen=True, slots=True)
class PatrolPlan:
    """What to patrol: ``points`` in order, ``count`` rounds (``FOREVER``: -1), and how close
    [m] the robot must pass each point before heading for the next."""

    points: tuple[str, ...]
    count: int = 1
    tolerance: float = 0.5

    def __post_init__(self) -> None:
        if len(self.points) < 2:
            raise InvalidRequest("points", f"needs at least 2 points, got {len(self.points)}")
        if self.count != FOREVER and self.count < 1:
            raise InvalidRequest("count", f"must be >= 1 or -1 (forever), got {self.count}")
        if not self.tolerance > 0.0:
            raise InvalidRequest("tolerance", f"must be > 0, got {self.tolerance}")


class Patrol:
    """The progress of one patrol: which round, which point, and how it ended."""

    def __init__(self, patrol_id: int, plan: PatrolPlan) -> None:
        self.patrol_id = patrol_id
        self.plan = plan
        self.round = 1
        self.index = 0
        self.state = PatrolState.RUNNING

    @property
    def point(self) -> str:
        """The point of the current leg."""
        return self.plan.points[self.index]

    @property
    def running(self) -> bool:
        return self.state is PatrolState.RUNNING

    def leg_ended(self, succeeded: bool) -> str | None:
        """The current leg ended; returns the next leg's point, or ``None`` when the patrol is
        over (``state`` says how)."""
        if not self.running:
            return None
        if not succeeded:
            log.warning("patrol %d: leg to %r failed, going on", self.patrol_id, self.point)
        last_round = self.plan.count != FOREVER and self.round >= self.plan.count
        if self.index + 1 < len(self.plan.points):
            self.index += 1
            return self.point
        if last_round:
            self.state = PatrolState.SUCCEEDED if succeeded else PatrolState.FAILED
            return None
        self.round += 1
        self.index = 0
        return self.point

    def cancel(self) -> bool:
        """End a running patrol as canceled; ``False`` if it was not running."""
        if not self.running:
            return False
        self.state = PatrolState.CANCELED
        return True
