"""The doors as the status shows them: the one the robot waits at, those it passes, and its
floor's doors open or closed.

A status reader (the console, a dialect, a supervisor) wants to know why a robot stands still
before a door and whether the doors round it are open, without asking ``GET /api/doors`` at the
status' rate. The snapshot carries that in a few bytes: the status goes out at 10 Hz on the
WebSocket, so a door is its name and state, never its geometry (that is ``GET /api/doors``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from polynav.robot.door import Door


@dataclass(frozen=True, slots=True)
class DoorsView:
    """The doors at one instant, by name.

    Attributes:
        waiting_for: the door the robot stands paused before until it opens, if any.
        passing: the doors the robot holds open to pass now (granted and asked open), sorted.
        states: each door of the robot's floor and its state (``closed``, ``opening``,
            ``open``, ``closing``), sorted by name.
    """

    waiting_for: str | None
    passing: tuple[str, ...]
    states: tuple[tuple[str, str], ...]

    def state_of(self, name: str | None) -> str | None:
        """Door ``name``'s state, if it is on the robot's floor."""
        return dict(self.states).get(name) if name is not None else None

    def to_dict(self) -> dict[str, object]:
        """``{"waiting_for": {"name", "state"} | null, "passing": [{"name", "state"}],
        "floor": {name: state}}``."""
        waiting = (None if self.waiting_for is None
                   else {"name": self.waiting_for, "state": self.state_of(self.waiting_for)})
        return {
            "waiting_for": waiting,
            "passing": [{"name": name, "state": self.state_of(name)} for name in self.passing],
            "floor": dict(self.states),
        }


def doors_view(doors: Mapping[str, Door], floor: str | None, waiting_for: str | None,
               passing: tuple[str, ...]) -> DoorsView:
    """The view of ``doors`` for a robot on ``floor`` (the door rule's ``waiting_for`` and
    ``held``). A door the robot uses is shown even off its floor (it just rode a lift)."""
    used = {name for name in (waiting_for, *passing) if name is not None}
    states = []
    for name, door in sorted(doors.items()):
        status = door.state()
        if status.spec.floor == floor or name in used:
            states.append((name, status.state.value))
    return DoorsView(waiting_for, passing, tuple(states))
