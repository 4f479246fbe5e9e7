"""Doors on the robot's way: asked for, opened, waited for, passed and closed behind it.

A part of :class:`~polynav.runtime.robot_runtime.RobotRuntime`, ticked every control period
after the navigation stack. The rule, as one robot keeps it:

1. While a goal runs, the robot looks ``lookahead`` metres along its planned path. A door of
   its floor whose leaf the path crosses there is asked for: the lease on ``door:<name>``
   (a lone robot's own lease book; in a building the fleet's, through VDA 5050 zone requests),
   named with the way it crosses the leaf
   (:meth:`~polynav.worlds.world.WorldDoor.crossing_flow`): robots going one way share it and
   go through together, and one coming the other way waits until they are through. (Held by
   one robot at a time, a robot held up on its way to the door by a walker kept it from two
   robots that had passed it and stood before the leaf, and they kept the corridor from it:
   floor 2's fire door, bench fleet seed 0.) Granted, the robot opens it
   (:meth:`~polynav.robot.door.Door.open`): it *controls* the door (Yunji ``01030``).
2. If the door is not granted and open by the time the robot is ``stop_distance`` from the
   leaf, the robot stops there (its goal is paused) and waits; once it is, it goes on.
3. Once the door is neither ahead nor under it (``clearance`` beyond the leaf), or while the
   goal stands paused for something else (the fleet's traffic rule: holding a door while
   waiting for a zone whose holder waits for the door would deadlock), the robot lets
   go of it (:meth:`~polynav.robot.door.Door.close`: it closes when no one else holds it) and
   gives the lease back (``01031``). A goal that ends lets go of every door it held.
4. No door is held for ever: one held ``max_control`` seconds is let go by force (``01032``), so
   a robot standing before or in a doorway does not keep a fire door open; it is not asked for
   again in that goal, which fails if the robot still has to go through (the door named); and
   no robot waits for ever: a
   door not open ``open_timeout`` seconds after it was granted and asked open fails the goal with
   the door named (``door fire_door_west did not open within 30 s (its controller does not
   answer)``); the wait for the grant is bounded by the lease book (``max_wait``, ``max_hold``).

The planner plans through doors: their leaves are *passable* to the costmap (the lidar's marks
there are not kept, :meth:`polynav.maps.costmap.Costmap.set_passable`), or no route would ever
cross a closed door; step 2 is what keeps the robot from driving into one on its path. Off its
path (a step aside from a walker, a recovery's back-up) nothing did: a door that stands shut
and that the robot neither holds nor has on its way ahead is drawn LETHAL on the body's costmap
(:meth:`polynav.maps.costmap.Costmap.set_shut_doors`), which the global planner does not see.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import ClassVar, Protocol

import numpy as np
import numpy.typing as npt

from polynav.errors import ConfigError, check_positive
from polynav.geometry import Pose2D
from polynav.maps.keepout import VirtualWall
from polynav.maps.map import MapInfo
from polynav.nav.attempt import FailureReason, NavigationState
from polynav.nav.stack import NavigationStack
from polynav.planning.path import Path, segment_crossings
from polynav.robot.door import Door, DoorState
from polynav.runtime.events import RuntimeEvent
from polynav.runtime.lift_sessions import LiftSessions
from polynav.worlds.world import WorldDoor

log = logging.getLogger(__name__)

_KEY = "doors."
PASSABLE_HALF_WIDTH = 0.1
"""[m] the lidar marks nothing this close to a door's segment (its leaf and the noise round it)."""
LEAF_THICKNESS = 0.1
"""[m] how thick a shut leaf is drawn on the body's costmap (a real leaf, and the simulator's)."""


@dataclass(frozen=True, slots=True)
class DoorConfig:
    """Distances and timings of the door rule.

    Attributes:
        lookahead: how far along the path a door is asked for and opened [m].
        stop_distance: a robot whose door is not open stops this far before its leaf [m].
        clearance: a robot this far past the leaf (or off its path) lets go of it [m].
        open_timeout: a door not open this long after it was granted and asked open fails
            the goal [s] (the wait for the grant is bounded by the lease book).
        max_control: a door held this long is let go by force [s].
        keep_margin: a door asked for stays asked for until it is this much beyond
            ``lookahead`` [m] (re-plans a little longer do not give it back).
    """

    lookahead: float = 4.0
    stop_distance: float = 0.9
    clearance: float = 0.8
    open_timeout: float = 30.0
    max_control: float = 90.0
    keep_margin: float = 1.0

    def __post_init__(self) -> None:
        check_positive(self, _KEY, ("lookahead", "stop_distance", "clearance", "open_timeout",
                                    "max_control", "keep_margin"))
        if self.stop_distance >= self.lookahead:
            raise ConfigError(_KEY + "stop_distance", "must be shorter than lookahead")


# -- events -----------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class DoorControlStarted(RuntimeEvent):
    """The robot was granted door ``door`` and asked it open, on attempt ``attempt_id``."""

    kind: ClassVar[str] = "door_control_started"

    attempt_id: int
    door: str


@dataclass(frozen=True, slots=True)
class DoorControlFinished(RuntimeEvent):
    """The robot let go of door ``door`` (passed it, or its goal ended)."""

    kind: ClassVar[str] = "door_control_finished"

    attempt_id: int
    door: str


@dataclass(frozen=True, slots=True)
class DoorControlForced(RuntimeEvent):
    """The robot held door ``door`` ``held`` seconds, too long: it was let go by force."""

    kind: ClassVar[str] = "door_control_forced"

    attempt_id: int
    door: str
    held: float


# -- the rule ---------------------------------------------------------------------------------


class DoorRobot(Protocol):
    """What the rule reads of and does to its robot (the runtime)."""

    @property
    def robot_id(self) -> str: ...

    @property
    def navigation_stack(self) -> NavigationStack | None: ...

    def _floor_now(self) -> str | None: ...

    def _status_pose(self) -> Pose2D: ...

    def _publish(self, event: RuntimeEvent) -> None: ...

    def _door_attempt_id(self) -> int: ...


@dataclass(slots=True)
class _Use:
    """A door the robot needs now: asked for at ``asked``, controlled since ``opened``."""

    asked: float
    flow: str  # the way the robot crosses (its lease is shared with robots going that way)
    opened: float | None = None


class DoorPassage:
    """One robot's side of the door rule (see the module docstring).

    Args:
        robot: the runtime.
        doors: the building's doors by name (read each tick: a real site's may change).
        leases: who may use a door, by door name (the seam of lift sessions, of kind
            ``door``: leases on ``door:<name>``).
        config: distances and timings.
    """

    def __init__(self, robot: DoorRobot, doors: Callable[[], Mapping[str, Door]],
                 leases: LiftSessions, config: DoorConfig | None = None) -> None:
        self._robot = robot
        self._doors = doors
        self.leases = leases
        self.config = config or DoorConfig()
        self._using: dict[str, _Use] = {}
        # Let go by force, with how long it was held: not asked again in this attempt.
        self._forced: dict[str, float] = {}
        self._paused_for: str | None = None
        self._we_paused = False  # the goal stands paused by this rule, not another
        self._attempt = 0
        self._passable_for: tuple[int, str | None] | None = None
        self._shut_for: tuple[int, tuple[str, ...]] | None = None
        self._path_crossings: _Crossings | None = None
        self.failure: str | None = None
        """Why the last goal was failed by the rule, for the status."""

    @property
    def waiting_for(self) -> str | None:
        """The door the robot stands waiting for, if any."""
        return self._paused_for

    @property
    def held(self) -> tuple[str, ...]:
        """The doors the robot controls now, sorted."""
        return tuple(sorted(d for d, use in self._using.items() if use.opened is not None))

    def use_leases(self, leases: LiftSessions) -> None:
        """Take door leases from ``leases`` (the fleet's) from now on."""
        self.leases = leases

    def tick(self, now: float) -> None:
        """Follow the rule for one control period."""
        robot = self._robot
        stack = robot.navigation_stack
        floor = robot._floor_now()
        doors: dict[str, Door] = {}
        specs: dict[str, WorldDoor] = {}  # read once a tick: a door's spec does not change
        for name, door in self._doors().items():
            spec = door.state().spec
            if spec.floor == floor:
                doors[name], specs[name] = door, spec
        if stack is not None:
            self._mark_passable(stack, floor, doors)
        navigator = stack.navigator if stack is not None else None
        active = navigator is not None and navigator.state in (
            NavigationState.RUNNING, NavigationState.PAUSED)
        if not active or navigator is None:
            self._let_go_all(now)
            self._forced.clear()
            self._paused_for = None
            self._we_paused = False
            if stack is not None:
                self._mark_shut(stack, doors, robot._status_pose(), {})
            return
        attempt = navigator.attempt
        attempt_id = attempt.attempt_id if attempt is not None else 0
        if attempt_id != self._attempt:
            self._let_go_all(now)
            self._forced.clear()
            self._attempt = attempt_id
            self._paused_for = None
            self._we_paused = False
        pose = robot._status_pose()
        path = navigator.path
        way = _way_from(path, pose) if doors else None  # no door, no crossing
        self._path_crossings = _crossings_of(path, specs, self._path_crossings)
        crossings = _first_crossings(way, self._path_crossings, specs)
        ahead = self._ahead(crossings)
        in_doorway = {name for name, spec in specs.items()
                      if spec.distance_to(pose.x, pose.y) < self.config.clearance}
        # A goal paused for something else (the traffic rule's zone, an operator) holds no
        # door ahead while it waits: holding one while waiting for a zone whose holder waits
        # for that door would be the hold-and-wait deadlock. It asks again once resumed.
        waiting_elsewhere = (navigator.state is NavigationState.PAUSED
                             and not self._we_paused)
        needed = set() if waiting_elsewhere else {name for name, _ in ahead}
        needed |= {name for name in self._using if name in in_doorway}
        if navigator.path is None and not waiting_elsewhere:
            # Between plans (blocked, re-planning) the way is not known: a door asked for
            # and still within reach is kept rather than given back and asked for again.
            reach = self.config.lookahead + self.config.keep_margin
            needed |= {name for name in self._using if name in specs
                       and specs[name].distance_to(pose.x, pose.y) <= reach}
        needed -= set(self._forced)
        for name in list(self._using):
            if name not in needed:
                self._let_go(name, now, forced=False)
        for name in sorted(needed):
            self._control(name, doors[name], pose, now)
        self._wait_or_go(ahead, doors, now)
        assert stack is not None  # it has a navigator
        self._mark_shut(stack, doors, pose, crossings)

    # -- a door's lease and controller ----------------------------------------------------

    def _control(self, name: str, door: Door, pose: Pose2D, now: float) -> None:
        use = self._using.get(name)
        if use is None:
            flow = door.state().spec.crossing_flow(pose.x, pose.y)
            use = self._using[name] = _Use(asked=now, flow=flow)
            log.info("%s: asks for door %s going %s", self._robot.robot_id, name, flow)
        leases = self.leases
        leases.request(name, now, use.flow)  # asks again after a rejection, keeping its place
        if not leases.granted(name, now):
            return
        if use.opened is None:
            use.opened = now
            self._robot._publish(DoorControlStarted(now, self._robot._door_attempt_id(), name))
        elif now - use.opened > self.config.max_control:
            log.warning("%s: held door %s %.0f s: let go by force", self._robot.robot_id,
                        name, now - use.opened)
            self._robot._publish(DoorControlForced(now, self._robot._door_attempt_id(), name,
                                                        now - use.opened))
            self._forced[name] = now - use.opened
            self._let_go(name, now, forced=True)
            return
        door.open(self._robot.robot_id)

    def _let_go(self, name: str, now: float, *, forced: bool) -> None:
        use = self._using.pop(name, None)
        if use is None:
            return
        door = self._doors().get(name)
        if door is not None:
            door.close(self._robot.robot_id)
        self.leases.release(name, now)
        if use.opened is not None and not forced:
            self._robot._publish(DoorControlFinished(now, self._robot._door_attempt_id(), name))
        log.info("%s: lets go of door %s", self._robot.robot_id, name)

    def _let_go_all(self, now: float) -> None:
        for name in list(self._using):
            self._let_go(name, now, forced=False)

    # -- waiting before a door --------------------------------------------------------------

    def _wait_or_go(self, ahead: list[tuple[str, float]], doors: Mapping[str, Door],
                    now: float) -> None:
        stack = self._robot.navigation_stack
        assert stack is not None
        navigator = stack.navigator
        blocking = None
        for name, distance in ahead:
            if distance > self.config.stop_distance:
                break
            if not self._open_for_us(name, doors[name]):
                blocking = name
                break
        if blocking is None:
            waited, self._paused_for = self._paused_for, None
            if waited is not None and self._we_paused and (
                    navigator.state is NavigationState.PAUSED):
                log.info("%s: door %s open, going on", self._robot.robot_id, waited)
                navigator.resume(now)
            self._we_paused = False
            return
        # A goal paused for something else (the fleet's traffic rule, an operator) is left
        # as it is; one resumed by it while the door is shut is paused again.
        if navigator.state is NavigationState.RUNNING:
            navigator.pause(now, make_way=True)
            self._we_paused = True
            if self._paused_for != blocking:
                log.info("%s: waits for door %s", self._robot.robot_id, blocking)
        self._paused_for = blocking
        # Waiting for the lease is bounded by the lease book (max_wait, max_hold); waiting
        # for a granted door to open, here.
        if blocking in self._forced:
            self._give_up(blocking, f"door {blocking} was held {self._forced[blocking]:.0f} s, "
                                    "too long, and released by force", now)
            return
        use = self._using.get(blocking)
        if use is not None and use.opened is not None and (
                now - use.opened > self.config.open_timeout):
            status = doors[blocking].state()
            why = ("its controller does not answer" if not status.answering
                   else f"it is {status.state.value}")
            self._give_up(blocking, f"door {blocking} did not open within "
                                    f"{self.config.open_timeout:g} s ({why})", now)

    def _open_for_us(self, name: str, door: Door) -> bool:
        use = self._using.get(name)
        return use is not None and use.opened is not None and (
            door.state().state is DoorState.OPEN)

    def _give_up(self, name: str, message: str, now: float) -> None:
        self.failure = message
        log.warning("%s: %s", self._robot.robot_id, message)
        self._paused_for = None
        self._we_paused = False
        stack = self._robot.navigation_stack
        assert stack is not None
        stack.navigator.abort(FailureReason.DOOR_CLOSED, message, now)
        self._let_go_all(now)

    # -- geometry ------------------------------------------------------------------------------

    def _ahead(self, crossings: Mapping[str, float | None]) -> list[tuple[str, float]]:
        """The doors the way ahead crosses within ``lookahead`` (of ``crossings``, from
        :func:`_first_crossings`), with their distances along it, nearest first."""
        found: list[tuple[str, float]] = []
        for name, distance in crossings.items():
            # A door already asked for stays asked for a little beyond the lookahead, so a
            # re-plan a few centimetres longer does not give it back and ask again.
            reach = self.config.lookahead + (self.config.keep_margin if name in self._using
                                             else 0.0)
            if distance is not None and distance <= reach:
                found.append((name, distance))
        found.sort(key=lambda item: item[1])
        return found

    def _mark_shut(self, stack: NavigationStack, doors: Mapping[str, Door], pose: Pose2D,
                   crossings: Mapping[str, float | None]) -> None:
        """Draw the leaves of the doors that stand shut, and that the robot neither holds nor
        has on its way ahead, LETHAL on the body's costmap
        (:meth:`~polynav.maps.costmap.Costmap.set_shut_doors`; the planner still routes
        through them). Passable to the lidar's marks, a doorway looked free to every local
        move: a robot that had passed a fire door and let it close stepped back from a walker
        into its leaf (bench fleet, seed 4). A door the body already stands in is left off
        (a real door's safety beam keeps it from closing on it)."""
        touching = stack.costmap.config.robot_radius + 0.5 * LEAF_THICKNESS
        shut = []
        for name, door in doors.items():
            status = door.state()
            if (status.state is DoorState.OPEN or name in self._using
                    or status.spec.distance_to(pose.x, pose.y) < touching):
                continue
            shut.append(status.spec)
        shut = [spec for spec in shut if crossings.get(spec.name) is None]
        key = (id(stack.costmap), tuple(spec.name for spec in shut))
        if key == self._shut_for:
            return
        self._shut_for = key
        stack.costmap.set_shut_doors([
            VirtualWall(((spec.x1, spec.y1), (spec.x2, spec.y2)), LEAF_THICKNESS)
            for spec in shut])

    def _mark_passable(self, stack: NavigationStack, floor: str | None,
                       doors: Mapping[str, Door]) -> None:
        key = (id(stack.costmap), floor)
        if key == self._passable_for:
            return
        self._passable_for = key
        specs = [d.state().spec for d in doors.values()]
        mask = passable_mask(specs, stack.costmap.info) if specs else None
        stack.costmap.set_passable(mask)


@dataclass(frozen=True, slots=True)
class _Way:
    """The legs of a path ahead of the robot: their lengths, and the distance [m] from the
    robot to each leg's start."""

    legs: npt.NDArray[np.float64]
    before: npt.NDArray[np.float64]
    first: int
    """The path's leg index of the way's first leg."""


@dataclass(frozen=True, slots=True, eq=False)
class _Crossings:
    """Where the legs of one path cross the leaves of the doors of its floor: worked out once
    a plan, as a plan lasts many ticks, and looked up each tick from the leg the robot is at.
    Per door, the indices of the legs that cross it (ascending) and where along each."""

    path: Path
    doors: tuple[WorldDoor, ...]
    legs: tuple[npt.NDArray[np.intp], ...]
    where: tuple[npt.NDArray[np.float64], ...]

    @classmethod
    def of(cls, path: Path, doors: tuple[WorldDoor, ...]) -> _Crossings:
        points = path.points
        t = segment_crossings(points[:-1], points[1:],
                              np.array([(d.x1, d.y1) for d in doors], dtype=np.float64),
                              np.array([(d.x2, d.y2) for d in doors], dtype=np.float64))
        legs = tuple(np.flatnonzero(~np.isnan(t[:, j])) for j in range(len(doors)))
        return cls(path, doors, legs, tuple(t[k, j] for j, k in enumerate(legs)))


def _way_from(path: Path | None, pose: Pose2D) -> _Way | None:
    """The whole way ``path`` goes on from its point nearest the robot (measured once a tick
    for the doors ahead and the doors it will open); ``None`` without one."""
    if path is None or len(path) < 2:
        return None
    points = path.points
    k = int(np.argmin(np.hypot(points[:, 0] - pose.x, points[:, 1] - pose.y)))
    return _way_ahead(points, k, pose, math.inf)


def _crossings_of(path: Path | None, doors: Mapping[str, WorldDoor],
                  known: _Crossings | None) -> _Crossings | None:
    """The crossings of ``path`` with ``doors``: ``known`` when it is of them, else new."""
    if path is None or len(path) < 2 or not doors:
        return None
    specs = tuple(doors.values())
    if known is not None and known.path is path and known.doors == specs:
        return known
    return _Crossings.of(path, specs)


def _way_ahead(points: npt.NDArray[np.float64], k: int, pose: Pose2D,
               reach: float) -> _Way | None:
    """The legs from the path's point ``k`` (the one nearest the robot) that start within
    ``reach`` of the robot along the path; ``None`` when there is none."""
    start = math.hypot(points[k, 0] - pose.x, points[k, 1] - pose.y)
    way = points[k:]
    if way.shape[0] < 2:
        return None
    legs = np.hypot(*np.diff(way, axis=0).T)
    before = start + np.concatenate(([0.0], np.cumsum(legs)[:-1]))  # at each leg's start
    n = int(np.searchsorted(before, reach, side="right"))
    if n == 0:
        return None
    return _Way(legs[:n], before[:n], k)


def _first_crossings(way: _Way | None, crossings: _Crossings | None,
                     doors: Mapping[str, WorldDoor]) -> dict[str, float | None]:
    """For each door, the distance [m] along ``way`` to where it first crosses the door's
    segment (``None`` where it does not), from the crossings of the path ``way`` is on."""
    found: dict[str, float | None] = dict.fromkeys(doors)
    if way is None or crossings is None:
        return found
    end = way.first + way.legs.shape[0]
    for door, legs, where in zip(crossings.doors, crossings.legs, crossings.where,
                                 strict=True):
        k = int(np.searchsorted(legs, way.first))
        if k < legs.shape[0] and legs[k] < end:
            i = int(legs[k]) - way.first
            found[door.name] = float(way.before[i] + way.legs[i] * where[k])
    return found


def _crossing(points: npt.NDArray[np.float64], k: int, door: WorldDoor, lookahead: float,
              pose: Pose2D) -> float | None:
    """Distance [m] along the path from the robot (at the path's point ``k``) to where it
    first crosses ``door``'s segment, if within ``lookahead``.

    Measured from the path's point nearest the robot: the leg back to the robot may cross a
    door just passed, which is behind it, not ahead."""
    doors = {door.name: door}
    way = _way_ahead(points, k, pose, lookahead)
    found = _first_crossings(way, _crossings_of(Path(points), doors, None), doors)[door.name]
    return found if found is not None and found <= lookahead else None


def passable_mask(doors: list[WorldDoor], info: MapInfo) -> npt.NDArray[np.bool_]:
    """Cells ``[iy, ix]`` of a map within :data:`PASSABLE_HALF_WIDTH` of any door's segment."""
    mask = np.zeros((info.height, info.width), dtype=np.bool_)
    res = info.resolution
    for door in doors:
        half = PASSABLE_HALF_WIDTH + 0.5 * res
        x0, x1 = min(door.x1, door.x2) - half, max(door.x1, door.x2) + half
        y0, y1 = min(door.y1, door.y2) - half, max(door.y1, door.y2) + half
        ix0, iy0 = info.world_to_cell(x0, y0)
        ix1, iy1 = info.world_to_cell(x1, y1)
        ix0, iy0 = max(ix0, 0), max(iy0, 0)
        ix1, iy1 = min(ix1, info.width - 1), min(iy1, info.height - 1)
        if ix0 > ix1 or iy0 > iy1:
            continue
        gy, gx = np.mgrid[iy0:iy1 + 1, ix0:ix1 + 1]
        centres = info.cells_to_world(np.column_stack((gx.ravel(), gy.ravel())))
        near = np.array([door.distance_to(float(x), float(y)) <= half for x, y in centres])
        mask[gy.ravel()[near], gx.ravel()[near]] = True
    return mask
