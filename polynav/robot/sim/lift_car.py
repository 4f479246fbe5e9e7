"""The simulator's lift car: a :class:`~polynav.robot.lift.Lift` stepped on the scene's clock.

The car moves between its floors at a constant ``speed`` (floors ``floor_height`` apart by
level), opens and closes its doors in ``door_time``, holds them open while its session asks for
it, and closes them after ``door_time`` once the session ends. Its riders are the robot bodies
standing in its shaft on the floor where it stands, plus people put in with :meth:`board_people`
(so tests can fill it); the :class:`~polynav.robot.sim.scene.Scene` carries the bodies to the
new floor when the car arrives (:meth:`SimLiftCar.step` reports the arrival).

A car taken out of service (:meth:`set_mode`) ends its session and refuses requests; one
moving finishes its trip and opens its doors first, so no rider is shut in.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass

from polynav.errors import InvalidRequest
from polynav.robot.lift import (
    DoorRequest,
    DoorState,
    LiftBusy,
    LiftMode,
    LiftOutOfService,
    LiftRequest,
    LiftState,
    MotionState,
)
from polynav.worlds.world import LiftCar

log = logging.getLogger(__name__)

_EPS = 1e-9


@dataclass(frozen=True, slots=True)
class Arrival:
    """The car stopped at ``floor`` having left ``from_floor`` (the scene moves its riders)."""

    car: str
    from_floor: str
    floor: str


class SimLiftCar:
    """One simulated car (see the module docstring).

    Args:
        spec: the car from the world file.
        levels: each served floor's level (storey number), for the travel distance.
        riders: counts the robot bodies in the car at a floor (from the scene).
        now: the scene's clock.
    """

    def __init__(self, spec: LiftCar, levels: dict[str, int],
                 riders: Callable[[str], int], now: Callable[[], float]) -> None:
        self.spec = spec
        self._levels = {f: levels[f] for f in spec.floors}
        self._riders = riders
        self._now = now
        self._floor = spec.floors[0]
        self._height = self._level_height(self._floor)
        self._destination = self._floor
        self._departed_from: str | None = None
        self._door = DoorState.CLOSED
        self._door_progress = 0.0  # 0 closed .. 1 open
        self._door_wish = DoorRequest.CLOSED
        self._dwell_until: float | None = None
        self._mode = LiftMode.NORMAL
        self._session = ""
        self._people = 0

    # -- the Lift interface ----------------------------------------------------------------

    @property
    def name(self) -> str:
        return self.spec.name

    def state(self) -> LiftState:
        motion = MotionState.STOPPED
        if self._moving:
            up = self._level_height(self._destination) > self._height
            motion = MotionState.UP if up else MotionState.DOWN
        return LiftState(
            name=self.spec.name, floors=self.spec.floors, current_floor=self._floor,
            destination_floor=self._destination, door=self._door, motion=motion,
            mode=self._mode, session_id=self._session,
            riders=self._people + (0 if self._moving else self._riders(self._floor)),
            capacity=self.spec.capacity, stamp=self._now())

    def request(self, request: LiftRequest) -> None:
        if self._mode is LiftMode.OUT_OF_SERVICE:
            raise LiftOutOfService(f"lift {self.name} is out of service")
        if not request.session_id:
            raise InvalidRequest("session_id", "a lift request names its session")
        if self._session and self._session != request.session_id:
            raise LiftBusy(f"lift {self.name} is in session with {self._session}")
        if request.end_session:
            if self._session:
                log.info("lift %s: session of %s ended", self.name, self._session)
            self._session = ""
            self._door_wish = DoorRequest.CLOSED
            self._dwell_until = self._now() + self.spec.door_time
            return
        if request.floor not in self._levels:
            raise InvalidRequest(
                "floor", f"lift {self.name} does not serve floor {request.floor!r} "
                         f"(it serves {', '.join(self.spec.floors)})")
        if not self._session:
            log.info("lift %s: session of %s opened", self.name, request.session_id)
        self._session = request.session_id
        self._door_wish = request.door
        self._dwell_until = None
        if request.floor != self._destination:
            log.info("lift %s: %s asks for %s (doors %s)", self.name, request.session_id,
                     request.floor, request.door.value)
            self._destination = request.floor

    def expected_arrival(self, floor: str) -> float:
        if floor not in self._levels:
            raise InvalidRequest("floor", f"lift {self.name} does not serve floor {floor!r}")
        time = 0.0
        if self._door is not DoorState.CLOSED and floor != self._floor:
            time += self._door_progress * self.spec.door_time
        distance = abs(self._level_height(floor) - self._height)
        if distance > _EPS and self._moving:
            # A moving car finishes its trip first.
            to_destination = abs(self._level_height(self._destination) - self._height)
            distance = to_destination + abs(
                self._level_height(floor) - self._level_height(self._destination))
        time += distance / self.spec.speed
        if not (floor == self._floor and self._door is DoorState.OPEN):
            time += (1.0 - (self._door_progress if floor == self._floor else 0.0)
                     ) * self.spec.door_time
        return time

    def travel_time(self, from_floor: str, to_floor: str) -> float:
        for floor in (from_floor, to_floor):
            if floor not in self._levels:
                raise InvalidRequest("floor", f"lift {self.name} does not serve floor {floor!r}")
        distance = abs(self._level_height(to_floor) - self._level_height(from_floor))
        return distance / self.spec.speed + 2.0 * self.spec.door_time

    # -- simulator controls ----------------------------------------------------------------

    @property
    def mode(self) -> LiftMode:
        return self._mode

    def set_mode(self, mode: LiftMode) -> None:
        """Put the car in or out of service; out of service ends its session."""
        if mode is self._mode:
            return
        self._mode = mode
        log.info("lift %s: %s", self.name, mode.value)
        if mode is LiftMode.OUT_OF_SERVICE:
            # Riders get out: a moving car opens on arrival (see _travel), a standing one keeps
            # its doors as they are for a while, then closes them.
            self._session = ""
            if not self._moving:
                self._dwell_until = self._now() + 2.0 * self.spec.door_time

    def board_people(self, count: int) -> None:
        """Put ``count`` people in the car (negative: take them out), as riders."""
        self._people = max(0, self._people + count)

    # -- stepping ----------------------------------------------------------------------------

    def step(self, h: float) -> Arrival | None:
        """Advance ``h`` [s]: doors, then travel; the arrival when the car stops at a floor."""
        now = self._now()
        if self._dwell_until is not None and now >= self._dwell_until - _EPS:
            self._dwell_until = None
            self._door_wish = DoorRequest.CLOSED
        at_destination = self._destination == self._floor and not self._moving
        if at_destination and self._door_wish is DoorRequest.OPEN:
            self._move_doors(h, opening=True)
            return None
        if self._door_progress > _EPS:
            self._move_doors(h, opening=False)
            return None
        if at_destination:
            return None
        return self._travel(h)

    @property
    def _moving(self) -> bool:
        return abs(self._level_height(self._destination) - self._height) > _EPS or (
            self._departed_from is not None)

    def _move_doors(self, h: float, *, opening: bool) -> None:
        rate = h / self.spec.door_time
        if opening:
            self._door_progress = min(1.0, self._door_progress + rate)
            self._door = DoorState.OPEN if self._door_progress >= 1.0 - _EPS else (
                DoorState.OPENING)
        else:
            self._door_progress = max(0.0, self._door_progress - rate)
            self._door = DoorState.CLOSED if self._door_progress <= _EPS else DoorState.CLOSING

    def _travel(self, h: float) -> Arrival | None:
        if self._departed_from is None:
            self._departed_from = self._floor
            log.info("lift %s: leaves %s for %s", self.name, self._floor, self._destination)
        target = self._level_height(self._destination)
        step = self.spec.speed * h
        if abs(target - self._height) <= step + _EPS:
            self._height = target
            start = self._departed_from
            self._departed_from = None
            self._floor = self._destination
            log.info("lift %s: arrives at %s", self.name, self._floor)
            if self._mode is LiftMode.OUT_OF_SERVICE:
                self._door_wish = DoorRequest.OPEN
                self._dwell_until = self._now() + 4.0 * self.spec.door_time
            return Arrival(self.name, start, self._floor) if start != self._floor else None
        self._height += step if target > self._height else -step
        self._floor = self._nearest_floor()
        return None

    def _level_height(self, floor: str) -> float:
        base = min(self._levels.values())
        return (self._levels[floor] - base) * self.spec.floor_height

    def _nearest_floor(self) -> str:
        return min(self._levels, key=lambda f: abs(self._level_height(f) - self._height))
