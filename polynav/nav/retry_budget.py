"""When does an attempt give up? Failures counted by place and by time, not by distance.

A robot in a dense field blocks often, and each block is cheap: it clears, backs up, turns and
finds the way on a second later. Counting blocks until the robot has covered some distance (the
old rule: four blocks before 1 m of progress) ends a goal as "stuck" after six seconds of
perfectly good recovering in a tight spot. What marks a robot as really stuck is that it keeps
failing *at the same place* for *a long time*:

- a failure belongs to a place: failures farther than ``radius`` [m] from the robot are
  forgotten once it has left them behind (a detour round a post is progress even when it
  leads away from the goal for a while);
- the rung of the recovery ladder is the number of failures at this place, so each new failure
  here tries one more recovery before the re-plan;
- the attempt gives up when there have been more than ``max_retries`` failures here *and* the
  first of them is at least ``min_time`` [s] old. ``max_retries`` 0 gives up at the first
  failure, as a caller asking for no retries expects;
- and, because leaving a place is not always getting anywhere, the attempt also gives up after
  more than ``STALL_FACTOR x max_retries`` failures anywhere while the robot got no ``radius``
  closer to the goal, the first of them ``min_time`` old: a robot that fails at one side of a
  blockage, tries the other side, fails there and comes back, again and again, forgets each
  place on each swing but is counted here.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

from polynav.geometry import Pose2D

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class Failure:
    """One failure: when [s] and where."""

    stamp: float
    pose: Pose2D


#: Failures anywhere without getting closer to the goal, in units of ``max_retries``.
STALL_FACTOR = 3


@dataclass
class RetryBudget:
    """The failures of one attempt, by place and time (see the module docstring)."""

    max_retries: int
    radius: float
    min_time: float
    failures: list[Failure] = field(default_factory=list)
    stalled: list[Failure] = field(default_factory=list)  # since the robot last got closer
    mark: float = math.inf  # [m] distance to the goal when it last got ``radius`` closer

    def reset(self, max_retries: int | None = None) -> None:
        """A new attempt: no failures (and, if given, its own retry limit)."""
        self.failures.clear()
        self.stalled.clear()
        self.mark = math.inf
        if max_retries is not None:
            self.max_retries = max_retries

    def moved(self, pose: Pose2D, to_goal: float) -> None:
        """Forget the failures the robot has left behind (farther than ``radius`` from
        ``pose``), and every stalled one once it is ``radius`` closer to the goal [m]."""
        if self.failures and any(f.pose.distance_to(pose) > self.radius for f in self.failures):
            self.failures = [f for f in self.failures if f.pose.distance_to(pose) <= self.radius]
        if to_goal <= self.mark - self.radius or math.isinf(self.mark):
            self.mark = to_goal
            self.stalled.clear()

    def record(self, pose: Pose2D, to_goal: float, now: float) -> int:
        """Count a failure at ``pose``, ``to_goal`` [m] from the goal; returns the rung: the
        failures not left behind, this included."""
        self.moved(pose, to_goal)
        failure = Failure(now, pose)
        self.failures.append(failure)
        self.stalled.append(failure)
        return len(self.failures)

    def exhausted(self, now: float) -> bool:
        """Give up? More than ``max_retries`` failures here, or more than ``STALL_FACTOR``
        times that without getting closer, the first ``min_time`` ago."""
        if self.max_retries == 0:
            return bool(self.failures)
        here = len(self.failures) > self.max_retries
        if here and now - self.failures[0].stamp >= self.min_time:
            return True
        stalled = len(self.stalled) > STALL_FACTOR * self.max_retries
        return stalled and now - self.stalled[0].stamp >= self.min_time
