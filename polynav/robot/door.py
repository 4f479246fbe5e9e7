"""The door interface: what polynav asks of an electronic door or gate and what it reads back.

A door is opened for whoever needs it and closed once no one does. polynav drives it through
this small interface, like the lift's (:mod:`polynav.robot.lift`): :meth:`Door.open` and
:meth:`Door.close` name who asks (a robot's id, or ``"operator"`` for a person at the console),
and :meth:`Door.state` reports what the door does. The simulator's door
(:mod:`polynav.robot.sim.door`) implements it; a real door's controller implements it by
translating onto its own protocol (a relay board, a building's access-control API).

Rules a controller keeps (the robot relies on them):

- **Requests are per requester.** ``open(who)`` adds ``who`` to those holding the door open;
  ``close(who)`` takes it out. The door opens while anyone holds it and closes when no one does.
  Who may hold it is decided above the controller (the lease on ``door:<name>``).
- **It never closes on someone.** A door whose passage is occupied stays open (the safety beam
  of a real door) and closes once it is clear.
- **State is reported, never inferred.** The robot drives through only once it reads ``OPEN``.
  A controller that stops answering keeps reporting its last state (``answering`` False when
  it knows): the robot waits, then gives its goal up naming the door.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from polynav.robot.lift import DoorState
from polynav.worlds.world import WorldDoor

OPERATOR = "operator"
"""The requester a person at the console opens and closes doors as."""

__all__ = ["OPERATOR", "Door", "DoorState", "DoorStatus"]


@dataclass(frozen=True, slots=True)
class DoorStatus:
    """What a door reports.

    Attributes:
        spec: the door (its place, kind and timing).
        state: closed, opening, open or closing.
        holders: who holds it open now, sorted.
        answering: whether its controller answers requests.
        stamp: when this state was taken [s] (the controller's clock).
    """

    spec: WorldDoor
    state: DoorState
    holders: tuple[str, ...]
    answering: bool
    stamp: float

    @property
    def name(self) -> str:
        return self.spec.name


class Door(Protocol):
    """An electronic door or gate as polynav drives it (see the module docstring).

    Implementations answer :meth:`state` at once (the last state received) and take requests
    without blocking; the effect shows in later states.
    """

    @property
    def name(self) -> str:
        """The door's id (the lease book's resource is ``door:<name>``)."""
        ...

    def state(self) -> DoorStatus:
        """The door's latest state."""
        ...

    def open(self, requester: str) -> None:
        """Hold the door open for ``requester`` (again: nothing new).

        Raises:
            InvalidRequest: an empty requester.
        """
        ...

    def close(self, requester: str) -> None:
        """``requester`` no longer needs the door; it closes once no one holds it."""
        ...
