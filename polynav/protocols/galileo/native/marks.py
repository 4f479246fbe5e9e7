"""What the native commands add to GalileoStatus that the runtime has no word for.

A ``g n`` to a goal that does not exist leaves the robot still with ``targetStatus`` 3 (error,
§1.4.3) though no attempt was made; an angle command (``a``) reports in ``angleGoalStatus``.
The status encoder reads these marks; they fade when a newer attempt starts.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

from polynav.protocols.galileo.context import Context


@dataclass
class NativeMarks:
    """Attributes:
        bad_goal: the number of the last invalid ``g n``; shown while ``bad_goal_attempt`` is
            still the runtime's current attempt (no newer goal started).
        angle_task: the task of the last angle command (its state is ``angleGoalStatus``).
    """

    bad_goal: int | None = None
    bad_goal_attempt: int | None = None
    angle_task: str | None = None
    lock: threading.Lock = field(default_factory=threading.Lock)

    def mark_bad_goal(self, number: int, attempt: int | None) -> None:
        with self.lock:
            self.bad_goal, self.bad_goal_attempt = number, attempt

    def clear_bad_goal(self) -> bool:
        with self.lock:
            had = self.bad_goal is not None
            self.bad_goal = self.bad_goal_attempt = None
            return had

    def bad_goal_now(self, attempt: int | None) -> int | None:
        """The invalid goal number still shown, given the runtime's current attempt."""
        with self.lock:
            if self.bad_goal is not None and self.bad_goal_attempt != attempt:
                self.bad_goal = self.bad_goal_attempt = None
            return self.bad_goal


def marks(ctx: Context) -> NativeMarks:
    return ctx.state("galileo.native.marks", NativeMarks)
