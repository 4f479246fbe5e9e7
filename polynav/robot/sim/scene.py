"""The shared part of a simulation: one world, one clock, its people, and every robot body in it.

A :class:`Scene` is what several simulated robots have in common: the ground truth of each floor
(walls, obstacles placed at run time), the people walking it, and the simulated clock. Each robot
is a :class:`~polynav.robot.sim.simulation.Simulation` (a *body*: base, sensors, battery) added to
the scene; a lone ``Simulation`` makes a scene of its own, so one robot behaves exactly as before.

Robots see and touch one another: each body's lidar sees the other bodies on its floor as discs
(``robot_radius``: for a polygon footprint, the disc that holds it, so contact between robots is
judged a little early, never late), and a move that would newly overlap another body is not made
(a collision with a ``"robot"``).

A scene step is ordered so that every body sees the same world at the same time:

1. every floor's people walk, each stopping for any robot in their way;
2. each body in turn moves (or is stopped by a wall, a person or another robot), and its
   odometry, IMU and battery take in the step;
3. the clock advances;
4. each body's IMU and lidar sample when due, on the world as it now is.

With a single body this is exactly the order of the one-robot simulator. Robots simulated in
other processes join through :attr:`Scene.remote` (:mod:`polynav.robot.sim.remote_bodies`): discs
seen, stopped for and collided with like the scene's own bodies, but moved by their messages.
Each collision between two robots is also kept as a :class:`RobotContact` naming both.

The building's lift cars (:class:`~polynav.robot.sim.lift_car.SimLiftCar`, one per ``lifts:``
entry of the world) are stepped first; a car that arrives at a floor carries the bodies standing
in its shaft there (each keeps its pose: the shafts coincide), so a robot rides by standing in
the car. The world's doors (:class:`~polynav.robot.sim.door.SimDoor`) are stepped next: a door
not fully open has its leaf in its floor's ground truth. The world's carts and cabins
(:mod:`~polynav.robot.sim.carts`) stand on their legs, or move with the body carrying them.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from polynav.clock import ManualClock
from polynav.errors import InvalidRequest
from polynav.maps.map import MapInfo
from polynav.robot.sim.carts import CartYard
from polynav.robot.sim.charger import SimCharger
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.door import SimDoor
from polynav.robot.sim.lift_car import Arrival, SimLiftCar
from polynav.robot.sim.people import Person, as_circles
from polynav.robot.sim.remote_bodies import RemoteBodies
from polynav.site import PointKind
from polynav.worlds.world import World, WorldDoor, WorldFloor

if TYPE_CHECKING:
    from polynav.robot.sim.simulation import Simulation

log = logging.getLogger(__name__)

NO_CIRCLES = np.empty((0, 3), dtype=np.float64)
_EPS = 1e-9


@dataclass(frozen=True, slots=True)
class RobotContact:
    """Body ``robot`` moved into robot ``other`` (a body of this scene or a remote one) at
    ``stamp`` [s]."""

    stamp: float
    robot: str
    other: str
    remote: bool


@dataclass(frozen=True, slots=True, eq=False)
class FloorState:
    """What the scene keeps per floor: ground truth ready for the kernels, its people, and its
    chargers with the segments of their plates (rows ``x0, y0, x1, y1``, all chargers)."""

    floor: WorldFloor
    occupied: npt.NDArray[np.bool_]
    info: MapInfo
    people: list[Person]
    chargers: tuple[SimCharger, ...]
    charger_segments: npt.NDArray[np.float64]


class Scene:
    """One world on one clock, shared by the robot bodies in it (see the module docstring).

    Args:
        world: the ground truth.
        config: the physics settings (the step period); every body must share its period.
        people: whether the floors' walkers walk.

    Raises:
        InvalidRequest: a floor map whose origin is rotated.
    """

    def __init__(self, world: World, config: SimConfig, *, people: bool = True) -> None:
        self.world = world
        self.config = config
        self.clock = ManualClock()
        self.floors = {f.name: floor_state(f, config) for f in world.floors}
        self.people_enabled = people
        self._bodies: list[Simulation] = []
        self.remote: RemoteBodies | None = None
        """Robots simulated elsewhere, drawn here too; None: this scene's bodies only."""
        self.robot_contacts: list[RobotContact] = []
        levels = {f.name: f.level for f in world.floors}
        self.lifts: dict[str, SimLiftCar] = {
            car.name: SimLiftCar(car, levels, self._rider_counter(car.name), self.clock.now)
            for car in world.lifts
        }
        self.doors: dict[str, SimDoor] = {
            door.name: SimDoor(door, self.floors[door.floor].occupied,
                               self.floors[door.floor].info, self._door_occupied,
                               self.clock.now)
            for door in world.doors
        }
        self.carts = CartYard(world.carts)
        """The world's carts and cabins (:mod:`~polynav.robot.sim.carts`)."""

    def _door_occupied(self, door: WorldDoor, margin: float) -> bool:
        """Whether a body or a person stands within ``margin`` [m] of ``door``'s leaf."""
        for body in self._bodies:
            pose = body.true_pose
            if body.floor == door.floor and door.distance_to(pose.x, pose.y) <= (
                    body.config.robot_radius + margin):
                return True
        if self.people_enabled:
            for person in self.floors[door.floor].people:
                pose = person.pose
                if door.distance_to(pose.x, pose.y) <= person.radius + margin:
                    return True
        return False

    def _rider_counter(self, car: str) -> Callable[[str], int]:
        def count(floor: str) -> int:
            return len(self.bodies_in_car(car, floor))
        return count

    def bodies_in_car(self, car: str, floor: str) -> list[Simulation]:
        """The bodies standing in car ``car``'s shaft on ``floor``."""
        shaft = self.world.lift(car).shaft
        return [b for b in self._bodies
                if b.floor == floor and shaft.contains(b.true_pose.x, b.true_pose.y)]

    @property
    def bodies(self) -> tuple[Simulation, ...]:
        """The robots in the scene, in the order they were added (and are stepped)."""
        return tuple(self._bodies)

    def add(self, body: Simulation) -> None:
        """Put ``body`` into the scene (its constructor does this).

        Raises:
            InvalidRequest: its physics period differs from the scene's.
        """
        if not math.isclose(body.config.physics_period, self.config.physics_period):
            raise InvalidRequest("physics_rate", "every robot in a scene steps at one rate")
        self._bodies.append(body)

    def robots_near(self, body: Simulation) -> npt.NDArray[np.float64]:
        """(K, 3) rows of x, y, radius [m]: the other bodies on ``body``'s floor."""
        others = [b for b in self._bodies if b is not body and b.floor == body.floor]
        remote = self._remote(body.floor)
        if not others:
            return remote
        out = np.empty((len(others), 3), dtype=np.float64)
        for k, b in enumerate(others):
            pose = b.true_pose
            out[k, 0], out[k, 1], out[k, 2] = pose.x, pose.y, b.config.robot_radius
        return np.concatenate((out, remote)) if remote.shape[0] else out

    def _remote(self, floor: str) -> npt.NDArray[np.float64]:
        if self.remote is None:
            return NO_CIRCLES
        return self.remote.circles(floor, self.clock.now())

    def people_circles(self, floor: str) -> npt.NDArray[np.float64]:
        """(K, 3) rows of x, y, radius [m] of the people on ``floor`` (none while they are off)."""
        people = self.floors[floor].people
        return as_circles(people) if self.people_enabled and people else NO_CIRCLES

    def step(self, dt: float | None = None) -> None:
        """Advance one physics period, or ``dt`` [s] in equal steps no longer than one period.

        Raises:
            InvalidRequest: ``dt`` is not positive.
        """
        period = self.config.physics_period
        if dt is None:
            self._substep(period)
            return
        if not dt > 0.0:
            raise InvalidRequest("dt", f"must be > 0, got {dt}")
        n = max(1, math.ceil(dt / period - _EPS))
        for _ in range(n):
            self._substep(dt / n)

    def _substep(self, h: float) -> None:
        # Nanosecond stamps: sums of 0.02 s would drift off the grid (2.0000000000000013).
        now = round(self.clock.now() + h, 9)
        for car in self.lifts.values():
            arrival = car.step(h)
            if arrival is not None:
                self._carry(arrival)
        for door in self.doors.values():
            door.step(h)
        people: dict[str, npt.NDArray[np.float64]] = {}
        if self.people_enabled:
            disks: dict[str, list[tuple[float, float, float]]] = {}
            for body in self._bodies:
                pose = body.true_pose
                disks.setdefault(body.floor, []).append(
                    (pose.x, pose.y, body.config.robot_radius))
            for name, state in self.floors.items():
                robots = disks.get(name, [])
                if self.remote is not None:
                    robots = robots + [(float(x), float(y), float(r))
                                       for x, y, r in self._remote(name)]
                for person in state.people:
                    person.step_among(h, robots)
            # Only the floors a body stands on: no one else reads them (a body changes floor
            # in the lift step above, not below).
            people = {name: as_circles(self.floors[name].people) if self.floors[name].people
                      else NO_CIRCLES for name in disks}
        for body in self._bodies:  # each sees where the ones before it have moved to
            hits = len(body._collisions)
            body._move(h, now, people.get(body.floor, NO_CIRCLES), self.robots_near(body))
            self.carts.follow(body.name, body.floor, body.true_pose)
            if len(body._collisions) > hits and body._collisions[-1].obstacle == "robot":
                self._note_contact(body, now)
        self.clock.set(now)
        for body in self._bodies:
            # The other bodies' discs matter to the lidar only, which samples on a fraction of
            # the steps: gather them for a body whose scan is due (gathering has no side
            # effects, and sensing moves no one, so each body sees the same others).
            others = self.robots_near(body) if body.scan_due(now) else NO_CIRCLES
            body._sense(now, people.get(body.floor, NO_CIRCLES), others)


    def _note_contact(self, body: Simulation, now: float) -> None:
        """Name the robot ``body`` just moved into: the nearest other one on its floor."""
        pose = body.true_pose
        best: tuple[float, str, bool] | None = None
        for other in self._bodies:
            if other is not body and other.floor == body.floor:
                d = math.hypot(other.true_pose.x - pose.x, other.true_pose.y - pose.y)
                if best is None or d < best[0]:
                    best = (d, other.name, False)
        if self.remote is not None:
            names = self.remote.serials_on(body.floor, self.clock.now())
            for (x, y, _), name in zip(self._remote(body.floor), names, strict=True):
                d = math.hypot(float(x) - pose.x, float(y) - pose.y)
                if best is None or d < best[0]:
                    best = (d, name, True)
        if best is not None:
            self.robot_contacts.append(RobotContact(now, body.name, best[1], best[2]))

    def _carry(self, arrival: Arrival) -> None:
        for body in self.bodies_in_car(arrival.car, arrival.from_floor):
            body.teleport(arrival.floor, body.true_pose)


def floor_state(floor: WorldFloor, config: SimConfig) -> FloorState:
    """A floor's ground truth and people, ready for stepping.

    Raises:
        InvalidRequest: the floor map's origin is rotated.
    """
    info = floor.map.info
    if info.origin.theta != 0.0:
        raise InvalidRequest("floor", f"{floor.name}: the simulator needs a map origin with zero "
                                      "yaw")
    people = [
        Person(
            route, pause=config.person_pause, stop_distance=config.person_stop_distance,
            patience=config.person_patience,
        )
        for route in floor.people
    ]
    # A charger stands at each charger point, its face where the robot's front is when docked.
    reach = config.front_reach
    chargers = tuple(SimCharger.at(p.pose, reach, config.charger_plate)
                     for p in floor.points if p.kind is PointKind.CHARGER)
    segments = (np.concatenate([c.segments for c in chargers]) if chargers
                else np.empty((0, 4), dtype=np.float64))
    occupied = np.ascontiguousarray(floor.map.occupied())
    return FloorState(floor, occupied, info, people, chargers, segments)
