"""When does an attempt give up? Failures counted by place and by time, not by distance.

A robot in a dense field blocks often, and each block is cheap: it clears, backs up, turns and
finds the way on a second later. Counting blocks until the robot has covered some distance (the
old rule: four blocks before 1 m of progress) ends a goal as "stuck" after six seconds of
perfectly good recovering in a tight spot. What marks a robot as really stuck is that it keeps
failing *at the same place* for *a long time*:

- a failure belongs to a place: failures farther than ``radius`` [m] from the robot are
  forgotten once it has left them behind;
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

    def moved(self, pose: Pose2D) -> None:
        """Forget the failures the robot has left behind (farther than ``radius``)."""
        if self.failures and any(f.pose.distance_to(pose) > self.radius for f in self.failures):
            self.failures = [f for f in self.failures if f.pose.distance_to(pose) <= self.radius]

    def record(self, pose: Pose2D, now: float) -> int:
        """Count a failure at ``pose``; returns the rung: failures at this place, this included."""
        self.moved(pose)
        self.failures.append(Failure(now, pose))
        return len(self.failures)

    def exhausted(self, now: float) -> bool:
        """Give up? More than ``max_retries`` failures here, the first ``min_time`` ago."""
        if len(self.failures) <= self.max_retries:
            return False
        if self.max_retries == 0:
            return True
        return now - self.failures[0].stamp >= self.min_time
