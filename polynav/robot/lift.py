"""The lift interface: what polynav asks of a lift car and what it reads back.

A lift car is a resource shared by every robot (and person) in the building. polynav drives it
through this small interface, modelled on open-RMF's ``rmf_lift_msgs`` (``LiftRequest``,
``LiftState``): a robot that holds the car's *session* asks it to go to a floor with its doors
open (a call, then a ride), holds the doors open while it drives in or out, and ends the session
when it has left. The simulator's car (:mod:`polynav.robot.sim.lift_car`) implements it; a real
lift controller implements it by translating onto its own protocol (a relay board, a vendor's
REST or Modbus interface, an RMF lift adapter). See ``docs/lifts.md``.

Rules a controller keeps (the navigator relies on them):

- **One session at a time.** A request names its ``session_id`` (the robot's id). The first
  request of a free car opens the session; requests with another id are refused
  (:class:`LiftBusy`) until :attr:`LiftRequest.end_session` ends it. Who may open a session is
  decided above the controller (the fleet's lease on ``lift:<car>``), the controller only
  refuses a second owner.
- **A request is a destination and a door wish.** ``floor`` is where the car goes; ``door``
  is ``OPEN`` (open on arrival and hold open until the next request) or ``CLOSED``. A car asked
  for another floor closes its doors first and opens them on arrival when asked to.
- **State is reported, never inferred.** :class:`LiftState` says where the car is
  (``current_floor`` is the floor it stands at or last passed), whether it moves, its doors, its
  mode, its session owner and how many riders it carries. The robot enters only once it reads
  the doors ``OPEN`` at its floor with the car stopped.
- **Out of service** (:attr:`LiftMode.OUT_OF_SERVICE`) refuses every request
  (:class:`LiftOutOfService`); a car taken out of service mid-trip finishes the trip and opens
  its doors, so a rider is never shut in.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Protocol

from polynav.errors import Conflict


class DoorState(enum.Enum):
    """The car's doors (RMF ``LiftState.door_state``, with the moving states split out)."""

    CLOSED = "closed"
    OPENING = "opening"
    OPEN = "open"
    CLOSING = "closing"


class MotionState(enum.Enum):
    """Whether the car moves (RMF ``LiftState.motion_state``)."""

    STOPPED = "stopped"
    UP = "up"
    DOWN = "down"


class LiftMode(enum.Enum):
    """What the car is available for (RMF ``LiftState.current_mode``, reduced)."""

    NORMAL = "normal"
    OUT_OF_SERVICE = "out_of_service"


class DoorRequest(enum.Enum):
    """The door wish of a request (RMF ``LiftRequest.door_state``)."""

    CLOSED = "closed"
    OPEN = "open"


@dataclass(frozen=True, slots=True)
class LiftRequest:
    """One request to a car (RMF ``LiftRequest``).

    Attributes:
        session_id: who asks (the robot's id); opens the session on a free car.
        floor: the floor to go to (a floor name the car serves); ignored with ``end_session``.
        door: open on arrival and hold, or keep closed.
        end_session: give the car back (the doors close after their dwell; the car stays).
    """

    session_id: str
    floor: str = ""
    door: DoorRequest = DoorRequest.OPEN
    end_session: bool = False


@dataclass(frozen=True, slots=True)
class LiftState:
    """What a car reports (RMF ``LiftState``).

    Attributes:
        name: the car's id.
        floors: the floors it serves, lowest first.
        current_floor: the floor it stands at, or last passed while moving.
        destination_floor: where it is going (``current_floor`` when it stands).
        door: its doors.
        motion: whether it moves, and which way.
        mode: normal or out of service.
        session_id: the session's owner, ``""`` when the car is free.
        riders: robots and people in the car now.
        capacity: how many riders fit.
        stamp: when this state was taken [s] (the controller's clock).
    """

    name: str
    floors: tuple[str, ...]
    current_floor: str
    destination_floor: str
    door: DoorState
    motion: MotionState
    mode: LiftMode
    session_id: str
    riders: int
    capacity: int
    stamp: float

    @property
    def full(self) -> bool:
        """No room for another rider."""
        return self.riders >= self.capacity

    def ready_at(self, floor: str) -> bool:
        """Stopped at ``floor`` with the doors fully open: a robot may drive in or out."""
        return (self.current_floor == floor and self.motion is MotionState.STOPPED
                and self.door is DoorState.OPEN)


class LiftError(Conflict):
    """A request the car cannot take now (HTTP 409 on the native API)."""


class LiftBusy(LiftError):
    """Another session owns the car."""


class LiftOutOfService(LiftError):
    """The car is out of service."""


class Lift(Protocol):
    """A lift car as polynav drives it (see the module docstring for the rules).

    Implementations answer :meth:`state` at once (no I/O wait: the last state received) and
    take a :meth:`request` without blocking; the effect shows in later states.
    """

    @property
    def name(self) -> str:
        """The car's id (the lease book's resource is ``lift:<name>``)."""
        ...

    def state(self) -> LiftState:
        """The car's latest state."""
        ...

    def request(self, request: LiftRequest) -> None:
        """Ask the car to go somewhere, hold or close its doors, or end the session.

        Raises:
            LiftBusy: another session owns the car.
            LiftOutOfService: the car is out of service.
            InvalidRequest: a floor the car does not serve.
        """
        ...

    def expected_arrival(self, floor: str) -> float:
        """How long [s] the car would take from now to stand open at ``floor`` if called now
        (travel, doors; not other sessions' trips). Used by the router to weigh cars."""
        ...

    def travel_time(self, from_floor: str, to_floor: str) -> float:
        """How long [s] a ride from ``from_floor`` to ``to_floor`` takes, doors closing at the
        start and opening at the end included."""
        ...
