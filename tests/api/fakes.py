"""A small scripted stand-in for RobotRuntime: the contract's commands over a real SiteStore,
EventBus, RobotSettings and StatusSnapshot, with motion replaced by ``advance`` jumping to goals.

It lets the API's routes and error mapping be tested without the simulator; the integration and
black-box tests use the real runtime.
"""

from __future__ import annotations

import datetime as dt
import functools
import threading
from collections.abc import Callable, Mapping
from typing import Any, TypeVar, cast

import numpy as np

from polynav.errors import Conflict, InvalidRequest, NotFound, NotLocalized
from polynav.geometry import Pose2D
from polynav.mapping.relocalization import Relocalization
from polynav.maps.map import Map, MapInfo
from polynav.nav.attempt import GoalOptions
from polynav.robot.door import OPERATOR, DoorStatus
from polynav.robot.lift import Lift, LiftMode, LiftRequest
from polynav.robot.profile import load_profile
from polynav.robot.sim.door import SimDoor
from polynav.robot.sim.lift_car import SimLiftCar
from polynav.runtime import events
from polynav.runtime.cart_jobs import Load
from polynav.runtime.event_bus import EventBus
from polynav.runtime.goal_commands import GoalFrame
from polynav.runtime.mapping_jobs import JobKind, MappingJob, MappingJobs
from polynav.runtime.mapping_status import MappingStatus
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.runtime.settings import RobotSettings
from polynav.runtime.status import StatusSnapshot
from polynav.runtime.task_commands import TaskCommands
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from polynav.worlds.carts import WorldCart
from polynav.worlds.world import World

T = TypeVar("T")
EPOCH = dt.datetime(2030, 1, 7, 9, 0)


class FakeCarts:
    """The cart service of a robot whose motion jumps to its results: the demo's loads listed,
    a dock's arguments checked as the real service checks them, then the load taken at once,
    and left at once."""

    def __init__(self, carts: tuple[WorldCart, ...]) -> None:
        self._carts = {c.name: c for c in carts}
        self.load: Any = None
        self.busy = False

    def loads(self) -> list[WorldCart]:
        return list(self._carts.values())

    def where(self, cart: WorldCart) -> tuple[str, Pose2D]:
        return cart.floor, cart.pose

    def status(self) -> dict[str, object]:
        load = self.load
        return {"load": None if load is None else {"name": load.cart.name,
                                                   "kind": load.cart.kind.value,
                                                   "mass": load.cart.mass},
                "action": None}

    def dock(self, *, cart: str | None = None, point: str | None = None,
             cabin_id: str | None = None) -> WorldCart:
        if (cart is None) == (point is None):
            raise InvalidRequest("cart", "give exactly one of cart and point")
        if cart is None or cart not in self._carts:
            raise InvalidRequest("cart", f"no cart or cabin {cart!r}")
        if self.load is not None:
            raise Conflict(f"the robot already carries {self.load.cart.name}")
        taken = self._carts[cart]
        if cabin_id is not None and cabin_id != taken.cabin_id:
            raise Conflict(f"the latch read cabin id {taken.cabin_id!r}, not {cabin_id!r}")
        self.load = Load(taken, Pose2D())
        return taken

    def leave(self, *, point: str | None = None, map_name: str | None = None) -> WorldCart:
        if self.load is None:
            raise Conflict("the robot carries no cart or cabin to leave")
        left, self.load = self.load.cart, None
        return cast(WorldCart, left)

    def cancel(self) -> bool:
        return False


class _TaskHost:
    """The fake as the real task commands see a runtime (its clock is a method there)."""

    def __init__(self, fake: FakeRuntime) -> None:
        self._fake = fake
        self.store = fake.store
        self.calendar_epoch = EPOCH

    def __getattr__(self, name: str) -> Any:
        return getattr(self._fake, name)

    def now(self) -> float:
        return self._fake.now

    def run_between_ticks(self, fn: Callable[[], T]) -> T:
        return fn()

    def publish(self, event: events.RuntimeEvent) -> None:
        self._fake._publish(event)

    def calendar_now(self) -> dt.datetime:
        return EPOCH + dt.timedelta(seconds=self._fake.now)

    def calendar_iso(self) -> str:
        return self.calendar_now().isoformat(timespec="seconds")


class _NoLidar:
    """The fake robot's sensors: no scan yet."""

    def read_scan(self) -> None:
        return None


class _NoPlan:
    """The fake's site queries: a running goal's plan is the straight line to it."""

    def __init__(self, fake: FakeRuntime) -> None:
        self._fake = fake

    def planned_path(self, max_points: int = 2000) -> list[tuple[float, float]]:
        fake = self._fake
        if fake.nav_state != "running" or fake.goal is None:
            return []
        return [(fake.pose.x, fake.pose.y), (fake.goal.x, fake.goal.y)][:max_points]


@functools.cache
def _demo_world() -> World:
    """The demo world, read once: the fake only reads its lifts and doors (the doors' grids
    copied)."""
    return load_world("demo")


class FakeRuntime:
    def __init__(self, store: SiteStore) -> None:
        self.store = store
        self.bus = EventBus()
        self._lock = threading.Lock()
        self._settings = RobotSettings()
        self.profile = load_profile("demo")
        self.now = 0.0
        self.mode = "free"
        self.map: str | None = None
        self.pose = Pose2D(0.0, 0.0, 0.0)
        self.velocity = (0.0, 0.0)
        self.estop_software = False
        self.nav_state = "idle"
        self.attempt = 0
        self.goal: Pose2D | None = None
        self.goal_point: str | None = None
        self.local_moves: list[tuple[float | None, float | None]] = []
        self.lost_in_a_hall = False
        self.mapping_started: tuple[str | None, str | None, Pose2D | None] | None = None
        self.jobs = MappingJobs()
        self._saving: MappingJob | None = None
        world = _demo_world()
        levels = {f.name: f.level for f in world.floors}
        self.cars = {car.name: SimLiftCar(car, levels, lambda floor: 0, lambda: self.now)
                     for car in world.lifts}
        self.keepouts_reloaded = 0
        self.doors = {  # real simulated doors on copies of the floors' grids
            d.name: SimDoor(d, np.ascontiguousarray(world.floor(d.floor).map.occupied()),
                            world.floor(d.floor).map.info, lambda door, margin: False,
                            lambda: self.now)
            for d in world.doors}
        self.carts = FakeCarts(world.carts)
        self.tasks = TaskCommands(cast(RobotRuntime, _TaskHost(self)))
        self.tasks.load()

    # -- lifts (real simulated cars, stepped by advance)
    @property
    def lifts(self) -> Mapping[str, Lift]:
        return self.cars

    def lift(self, car: str) -> Lift:
        if car not in self.cars:
            raise NotFound("lift", car)
        return self.cars[car]

    def request_lift(self, car: str, request: LiftRequest) -> None:
        self.lift(car).request(request)

    def set_lift_mode(self, car: str, mode: LiftMode) -> None:
        self.lift(car)
        self.cars[car].set_mode(mode)

    # -- doors (real simulated doors, stepped by advance)
    def door_states(self) -> list[DoorStatus]:
        return [door.state() for _, door in sorted(self.doors.items())]

    def _door(self, name: str) -> SimDoor:
        if name not in self.doors:
            raise NotFound("door", name)
        return self.doors[name]

    def open_door(self, name: str) -> DoorStatus:
        self._door(name).open(OPERATOR)
        return self._door(name).state()

    def close_door(self, name: str) -> DoorStatus:
        self._door(name).close(OPERATOR)
        return self._door(name).state()

    # -- helpers
    def _publish(self, event: events.RuntimeEvent) -> None:
        self.bus.publish(event)

    def _set_mode(self, new: str) -> None:
        self._publish(events.ModeChanged(self.now, self.mode, new))
        self.mode = new

    def advance(self, seconds: float) -> None:
        """Move the clock; a running goal is reached at once, teleop stops after 0.5 s."""
        with self._lock:
            for _ in range(round(seconds / 0.02)):
                for car in self.cars.values():
                    car.step(0.02)
                for door in self.doors.values():
                    door.step(0.02)
            self.now += seconds
            if self.nav_state == "running" and self.goal is not None:
                self.pose = self.goal
                self.nav_state = "succeeded"
                self._publish(events.NavigationSucceeded(self.now, self.attempt, 1.0))
            self.velocity = (0.0, 0.0)
            self._finish_job()

    # -- what the console's map view reads (GET /api/scene) and its keepout edits
    is_simulated = False  # no simulator: no people to show

    @property
    def map_name(self) -> str | None:
        return self.map

    @property
    def robot(self) -> _NoLidar:
        return _NoLidar()

    @property
    def queries(self) -> _NoPlan:
        return _NoPlan(self)

    def run_between_ticks(self, fn: Callable[[], T]) -> T:
        with self._lock:
            return fn()

    def reload_keepouts(self) -> None:
        self.keepouts_reloaded += 1

    # -- contract
    def status(self) -> StatusSnapshot:
        floors = {f.map_name: f.name for f in self.store.floors()}
        return StatusSnapshot(
            mode=self.mode, map=self.map, floor=floors.get(self.map or "floor1"),
            pose=self.pose, linear=self.velocity[0], angular=self.velocity[1],
            battery_percent=80.0, charging=False, estop_hardware=False,
            estop_software=self.estop_software, localization_state="tracking",
            localization_quality=1.0, navigation_state=self.nav_state, stamp=self.now,
            attempt_id=self.attempt or None, goal=self.goal, goal_point=self.goal_point,
            frame="odom" if self.map == "odom" else "map",
            mapping=self._mapping_status(),
        )

    def settings(self) -> RobotSettings:
        return self._settings

    def update_settings(self, changes: Mapping[str, object]) -> RobotSettings:
        self._settings = self._settings.apply(changes)
        return self._settings

    def start_navigation(
        self, map_name: str, *, point: str | None = None, pose: Pose2D | None = None
    ) -> None:
        self.store.map_record(map_name)
        if point is not None:
            pose = self.store.point(map_name, point).pose
        with self._lock:
            self._set_mode("busy")
            self.map = map_name
            if pose is not None:
                self.pose = pose
            self._set_mode("navigating")

    def start_mapless(self) -> None:
        with self._lock:
            if self.mode == "mapping":
                raise Conflict("mapping is running")
            self._set_mode("busy")
            self.map = "odom"
            self._set_mode("navigating")

    def stop_navigation(self) -> None:
        with self._lock:
            self._set_mode("busy")
            self.map = None
            self._set_mode("free")

    def set_initial_pose(self, pose: Pose2D) -> None:
        if self.mode != "navigating":
            raise Conflict("not navigating")
        self.pose = pose

    def relocalize(self) -> Relocalization:
        """Found where the fake robot is, unless ``lost_in_a_hall`` (then ambiguous)."""
        if self.mode != "navigating":
            raise Conflict("not navigating")
        if self.lost_in_a_hall:
            raise NotLocalized("relocalization failed: ambiguous")
        return Relocalization(self.pose, 0.93, 0.41)

    # -- mapping: a fixed little map "grows" as the fake advances

    def start_mapping(self, map_name: str | None = None, *, point: str | None = None,
                      pose: Pose2D | None = None) -> None:
        if self.mode != "free":
            raise Conflict(f"mapping starts from free (mode {self.mode})")
        if map_name is not None:
            self.store.map_record(map_name)  # NotFound
        self.mapping_started = (map_name, point, pose)
        self.jobs.new_session()
        self._set_mode("mapping")

    def _need_mapping(self) -> None:
        if self.mode != "mapping":
            raise Conflict("not mapping")

    def mapping_map(self) -> Map:
        self._need_mapping()
        return self.mapping_map_now()

    def mapping_map_now(self) -> Map:
        data = np.full((4, 6), -1, dtype=np.int8)
        data[1:3, 1:5] = 0
        data[0, :] = 100
        return Map(MapInfo(0.05, 6, 4, Pose2D(-0.1, -0.1, 0.0)), data)

    def save_mapping(self, name: str, *, overwrite: bool = False) -> object:
        self._need_mapping()
        if not overwrite and name in {m.name for m in self.store.maps()}:
            raise Conflict(f"a map called {name!r} exists")
        return self.store.save_map(name, self.mapping_map())

    def stop_mapping(self, name: str, *, overwrite: bool = False) -> object:
        record = self.save_mapping(name, overwrite=overwrite)
        self._set_mode("free")
        return record

    # -- save jobs: begun at once (the real runtime's checks), written on the next advance

    def _begin_job(self, kind: JobKind, name: str, overwrite: bool) -> MappingJob:
        if self.mode == "busy" and self._saving is not None:
            raise Conflict("mapping is stopping")
        self._need_mapping()
        if not overwrite and name in {m.name for m in self.store.maps()}:
            raise Conflict(f"a map called {name!r} exists")
        job = self.jobs.begin(kind, name, self.now)
        self._saving = job
        if kind is JobKind.STOP:
            self._set_mode("busy")
        return job

    def save_mapping_job(self, name: str, *, overwrite: bool = False) -> MappingJob:
        return self._begin_job(JobKind.SAVE, name, overwrite)

    def stop_mapping_job(self, name: str, *, overwrite: bool = False) -> MappingJob:
        return self._begin_job(JobKind.STOP, name, overwrite)

    def mapping_job(self, job_id: str) -> MappingJob:
        return self.jobs.get(job_id)

    def _finish_job(self) -> None:
        job, self._saving = self._saving, None
        if job is None:
            return
        self.store.save_map(job.name, self.mapping_map_now())
        self.jobs.end(job.id, self.now)
        if job.kind is JobKind.STOP:
            self._set_mode("free")

    def _mapping_status(self) -> MappingStatus | None:
        if self.mode != "mapping" and self._saving is None:
            return None
        grid = self.mapping_map_now()
        area = float(np.count_nonzero(grid.data >= 0)) * grid.info.resolution ** 2
        kind = "new" if self.mapping_started is None or self.mapping_started[0] is None else (
            "update")
        return MappingStatus(kind, None if kind == "new" else self.mapping_started[0], "off",
                             None, 0, area, 0, 0.0, self.jobs.session_job())

    def explore(self) -> None:
        self._need_mapping()

    def cancel_mapping(self) -> None:
        self._need_mapping()
        self._set_mode("free")

    def go_to(
        self, *, point: str | None = None, pose: Pose2D | None = None,
        map_name: str | None = None, options: GoalOptions | None = None,
        frame: GoalFrame | None = None,
    ) -> int:
        self.goal_options = options
        if self.mode != "navigating" or self.map is None:
            raise Conflict("not navigating: start navigation on a map first")
        if pose is not None and frame is GoalFrame.ROBOT:
            pose = self.pose.compose(pose)
        if map_name is not None:
            self.store.map_record(map_name)  # 404 for an unknown map, as the runtime
        if map_name is not None and map_name != self.map:
            raise InvalidRequest("map", f"goal on {map_name!r} while navigating on {self.map!r}")
        if point is not None:
            pose = self.store.point(self.map, point).pose
        assert pose is not None
        with self._lock:
            self.attempt += 1
            self.goal, self.goal_point, self.nav_state = pose, point, "running"
            self._publish(events.NavigationStarted(self.now, self.attempt, pose, point))
            return self.attempt

    def _need(self, state: str, what: str) -> None:
        if self.nav_state != state:
            raise Conflict(f"no goal to {what}")

    def cancel(self) -> None:
        if self.nav_state not in ("running", "paused"):
            raise Conflict("no goal to cancel")
        self.nav_state = "canceled"
        self._publish(events.NavigationCanceled(self.now, self.attempt, 0.5))

    def pause(self) -> None:
        self._need("running", "pause")
        self.nav_state = "paused"
        self._publish(events.NavigationPaused(self.now, self.attempt))

    def resume(self) -> None:
        self._need("paused", "resume")
        self.nav_state = "running"
        self._publish(events.NavigationResumed(self.now, self.attempt))

    def teleop(self, linear: float, angular: float) -> None:
        if self.nav_state in ("running", "paused"):
            raise Conflict("a goal is running")
        s = self._settings
        self.velocity = (
            max(-s.max_linear_velocity, min(s.max_linear_velocity, linear)),
            max(-s.max_angular_velocity, min(s.max_angular_velocity, angular)),
        )

    def set_software_estop(self, on: bool) -> None:
        self.estop_software = on
        self._publish(events.EStopChanged(self.now, False, on, on))

    def local_move(self, *, rotate: float | None = None, distance: float | None = None) -> None:
        if self.nav_state in ("running", "paused"):
            raise Conflict("a goal is running")
        self.local_moves.append((rotate, distance))
