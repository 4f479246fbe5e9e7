"""When does an attempt give up? Failures counted by place and by time, not by distance.

A robot in a dense field blocks often, and each block is cheap: it clears, backs up, turns and
finds the way on a second later. Counting blocks until the robot has covered some distance (the
old rule: four blocks before 1 m of progress) ends a goal as "stuck" after six seconds of
perfectly good recovering in a tight spot. What marks a robot as really stuck is that it keeps
failing *at the same place* for *a long time*:

- a failure belongs to a place: it is forgotten once the robot has left it behind, that is
  once the robot is farther than ``radius`` [m] from it *and* at least ``radius`` closer to the
  goal than it was there. Moving away alone is not enough: a robot that fails at one side of a
  blockage, backs off, tries the other side and fails there, and comes back, has got nowhere,
  and forgetting its failures on each swing would let it swing for ever;
- the rung of the recovery ladder is the number of failures at this place, so each new failure
  here tries one more recovery before the re-plan;
- the attempt gives up when there have been more than ``max_retries`` failures here *and* the
  first of them is at least ``min_time`` [s] old. ``max_retries`` 0 gives up at the first
  failure, as a caller asking for no retries expects.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

from polynav.geometry import Pose2D

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class Failure:
    """One failure: when [s] and where."""

    stamp: float
    pose: Pose2D
    to_goal: float  # [m] straight-line distance to the goal when it failed


@dataclass
class RetryBudget:
    """The failures of one attempt, by place and time (see the module docstring)."""

    max_retries: int
    radius: float
    min_time: float
    failures: list[Failure] = field(default_factory=list)

    def reset(self, max_retries: int | None = None) -> None:
        """A new attempt: no failures (and, if given, its own retry limit)."""
        self.failures.clear()
        if max_retries is not None:
            self.max_retries = max_retries

    def moved(self, pose: Pose2D, to_goal: float) -> None:
        """Forget the failures the robot has left behind: farther than ``radius`` from ``pose``
        and at least ``radius`` farther from the goal than ``to_goal`` [m]."""
        if self.failures and any(self._left_behind(f, pose, to_goal) for f in self.failures):
            self.failures = [f for f in self.failures if not self._left_behind(f, pose, to_goal)]

    def record(self, pose: Pose2D, to_goal: float, now: float) -> int:
        """Count a failure at ``pose``, ``to_goal`` [m] from the goal; returns the rung: the
        failures not left behind, this included."""
        self.moved(pose, to_goal)
        self.failures.append(Failure(now, pose, to_goal))
        return len(self.failures)

    def _left_behind(self, failure: Failure, pose: Pose2D, to_goal: float) -> bool:
        return (
            failure.pose.distance_to(pose) > self.radius
            and failure.to_goal - to_goal >= self.radius
        )

    def exhausted(self, now: float) -> bool:
        """Give up? More than ``max_retries`` failures here, the first ``min_time`` ago."""
        if len(self.failures) <= self.max_retries:
            return False
        if self.max_retries == 0:
            return True
        return now - self.failures[0].stamp >= self.min_time
