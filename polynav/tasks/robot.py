"""What a task may ask of its robot: the runtime's commands, as the task engine sees them.

The engine is a service below the runtime (DESIGN §1): it never imports the runtime. The
runtime hands it a :class:`TaskRobot` (:mod:`polynav.runtime.task_robot`) whose methods are
called between ticks, on the loop, and raise the runtime's errors
(:class:`~polynav.errors.PolynavError`) when the robot cannot do what is asked.
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Protocol

from polynav.geometry import Pose2D
from polynav.nav.attempt import GoalOptions


class GoalEnd(enum.Enum):
    """How a navigation goal ended."""

    SUCCEEDED = "succeeded"
    FAILED = "failed"
    CANCELED = "canceled"


@dataclass(frozen=True, slots=True)
class GoalOutcome:
    """A goal's end: how, and why it failed (a :class:`~polynav.nav.attempt.FailureReason`
    value such as ``"no path"``, or the runtime's message)."""

    end: GoalEnd
    reason: str = ""


class TaskRobot(Protocol):
    """The robot, for the task engine; every call between ticks."""

    def now(self) -> float:
        """The runtime's clock [s]."""
        ...

    def pose(self) -> Pose2D:
        """The pose estimate on the current map."""
        ...

    def current_map(self) -> str | None:
        """The map navigation runs on; ``None`` while not navigating."""
        ...

    def battery_percent(self) -> float: ...

    def charging(self) -> bool:
        """Whether the robot stands on a charger that charges it."""
        ...

    # -- navigation ----------------------------------------------------------------------------

    def navigate(self, *, point: str | None = None, pose: Pose2D | None = None,
                 map_name: str | None = None, options: GoalOptions | None = None) -> int:
        """Start a goal (on another map: across lifts and connections); its attempt id."""
        ...

    def goal_outcome(self, attempt_id: int) -> GoalOutcome | None:
        """How the goal ended; ``None`` while it runs."""
        ...

    def distance_remaining(self, attempt_id: int) -> float | None: ...

    def pause_goal(self, attempt_id: int) -> None: ...

    def resume_goal(self, attempt_id: int) -> None: ...

    def cancel_goal(self, attempt_id: int) -> None:
        """Cancel the goal if it still runs."""
        ...

    def switch_map(self, map_name: str, point: str | None) -> None:
        """Start navigation on ``map_name`` from ``point`` (the robot stands there)."""
        ...

    def navigation_ready(self, map_name: str) -> bool | None:
        """``True`` navigating on the map, ``None`` while loading, ``False`` if it did not
        start."""
        ...

    # -- motion --------------------------------------------------------------------------------

    def local_move(self, *, rotate: float | None = None, distance: float | None = None) -> None:
        """Turn on the spot [rad] or drive straight [m], checked against obstacles."""
        ...

    def local_move_active(self) -> bool: ...

    def stop_local_move(self) -> None: ...

    # -- devices -------------------------------------------------------------------------------

    def set_output(self, port: int, level: int) -> None:
        """Set an output of the base's IO bank."""
        ...

    def say(self, text: str) -> float:
        """Speak ``text``; how long it takes [s]."""
        ...

    def stop_speaking(self) -> None: ...

    def change_settings(self, changes: Mapping[str, Any]) -> dict[str, Any]:
        """Apply setting changes; the values they replaced."""
        ...
