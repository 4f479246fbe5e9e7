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
        angle_ended, angle_ended_attempt: whether that task was seen ended, and the runtime's
            attempt then; once another attempt starts (a newer goal) the mark fades, as
            ``bad_goal``'s does.
    """

    bad_goal: int | None = None
    bad_goal_attempt: int | None = None
    angle_task: str | None = None
    angle_ended: bool = False
    angle_ended_attempt: int | None = None
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


    def mark_angle_task(self, task: str) -> None:
        with self.lock:
            self.angle_task, self.angle_ended, self.angle_ended_attempt = task, False, None

    def angle_task_now(self, attempt: int | None) -> str | None:
        """The angle task still shown, given the runtime's current attempt."""
        with self.lock:
            if self.angle_ended and self.angle_ended_attempt != attempt:
                self._forget_angle_task()
            return self.angle_task

    def angle_task_ended(self, task: str, attempt: int | None) -> None:
        """The angle task ``task`` is over while ``attempt`` is the runtime's current one."""
        with self.lock:
            if self.angle_task == task and not self.angle_ended:
                self.angle_ended, self.angle_ended_attempt = True, attempt

    def forget_angle_task(self, task: str) -> None:
        with self.lock:
            if self.angle_task == task:
                self._forget_angle_task()

    def _forget_angle_task(self) -> None:
        self.angle_task, self.angle_ended, self.angle_ended_attempt = None, False, None


def marks(ctx: Context) -> NativeMarks:
    return ctx.state("galileo.native.marks", NativeMarks)
