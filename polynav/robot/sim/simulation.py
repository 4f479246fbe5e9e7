"""The simulation: one robot in a :class:`~polynav.worlds.world.World`, on simulated time.

:class:`Simulation` is one robot *body* in a :class:`~polynav.robot.sim.scene.Scene` (the world,
its people and the :class:`~polynav.clock.ManualClock`); alone it makes a scene of its own, and
several bodies made on one scene are several robots in one building, stepped together (each sees
and touches the others, see :mod:`~polynav.robot.sim.scene`). The scene advances everything by
fixed physics steps (``SimConfig.physics_rate``). Each step, in order:

1. every floor's people walk (on the robot's floor they stop for the robot, see
   :mod:`~polynav.robot.sim.people`);
2. the base ramps toward the last drive command (zero while the e-stop is pressed) and proposes
   its move; a move that would newly overlap a wall, a person or another robot is not made:
   the base stops
   dead where it stands and, unless it was already in contact, a :class:`Collision` is
   recorded (one per contact: the next counts once the robot has got clear again);
3. odometry and the IMU take in the step's true motion (odometry in its own frame, which starts
   at (0, 0, 0) where the body is created, as a real base's does where it is switched on), the
   battery drains (or charges while the robot stands docked on a charger point);
4. the clock advances, and the IMU and the lidar sample when they are due, stamped with the new
   time, so a scan describes the world as it is at its stamp.

Noise is deterministic for a seed: ``SeedSequence(seed).spawn`` gives each noise source (lidar,
odometry, IMU) its own generator, so adding draws to one never shifts another's. People are
deterministic without any randomness.
"""

from __future__ import annotations

import dataclasses
import logging
import math

import numpy as np
import numpy.typing as npt

from polynav.errors import Conflict, InvalidRequest
from polynav.geometry import Pose2D, Twist
from polynav.robot.interface import (
    BatteryState,
    DockLink,
    DockSignals,
    ImuReading,
    LaserScan,
    Odometry,
    PersonDetection,
    SignDetection,
)
from polynav.robot.sim import charger as charger_faults
from polynav.robot.sim.battery import Battery
from polynav.robot.sim.carts import SimCart
from polynav.robot.sim.charger import SimCharger, body_clearance
from polynav.robot.sim.collision import (
    Collision,
    Obstacle,
    body_wall_clearance,
    person_clearance,
)
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.diff_drive import DiffDrive
from polynav.robot.sim.imu import Imu
from polynav.robot.sim.lidar import Lidar
from polynav.robot.sim.odometry import WheelOdometry
from polynav.robot.sim.people_detector import PeopleDetector
from polynav.robot.sim.scene import FloorState, Scene
from polynav.robot.sim.sign_camera import seen_signs
from polynav.robot.sim.sim_robot import SimRobot
from polynav.robot.sim.wifi import VisibleNetwork, WirelessCard
from polynav.site import PointKind
from polynav.worlds.carts import CartKind
from polynav.worlds.world import World

log = logging.getLogger(__name__)

_EPS = 1e-9
LASER_SLOT_OBJECT = "laser_slot_object"
FAULTS = frozenset({LASER_SLOT_OBJECT}) | charger_faults.FAULTS
_SLOT_SECTOR = math.radians(40.0)  # what an object in the slot hides
_NO_SEGMENTS = np.empty((0, 4), dtype=np.float64)


class Simulation:
    """A simulated robot in a world.

    Args:
        world: the ground truth.
        config: robot, sensor and physics settings.
        seed: seeds every noise source.
        floor: floor to start on; defaults to the world's start floor.
        pose: true start pose; defaults to the world's start pose on the start floor, or to the
            floor's initial point on another floor.
        people: whether the floors' walkers walk (see :meth:`set_people`); a body joining a
            ``scene`` keeps the scene's setting.
        scene: the scene to join, with the robots already in it (several robots in one
            building, on one clock); a scene of its own if None.
        name: what logs call this robot.

    Raises:
        InvalidRequest: unknown floor, no start pose for it, a start pose inside an obstacle or
            another robot, a floor map whose origin is rotated, or a scene of another world.
    """

    def __init__(
        self,
        world: World,
        *,
        config: SimConfig = SimConfig(),  # noqa: B008 - frozen, so one shared default is safe
        seed: int = 0,
        floor: str | None = None,
        pose: Pose2D | None = None,
        people: bool = True,
        scene: Scene | None = None,
        name: str = "robot",
    ) -> None:
        if scene is None:
            scene = Scene(world, config, people=people)
        elif scene.world is not world:
            raise InvalidRequest("scene", "the scene simulates another world")
        self.world = world
        self.config = config
        self.name = name
        self._scene = scene
        self.clock = scene.clock
        self._floors = scene.floors
        self._floor = world.floor(floor or world.start_floor).name
        if pose is None:
            pose = self._default_pose(self._floor)
        lidar_seed, odometry_seed, imu_seed = np.random.SeedSequence(seed).spawn(3)
        now = self.clock.now()
        self._base = DiffDrive(config, pose)
        self._lidar = Lidar(config, np.random.default_rng(lidar_seed))
        # Odometry counts from zero here, as a real base's does where it is switched on; the
        # world pose of its frame is kept only to translate world poses for tests and benches.
        self._odometry_origin = pose
        self._odometry = WheelOdometry(config, np.random.default_rng(odometry_seed), now)
        self._imu = Imu(config, pose.theta, np.random.default_rng(imu_seed), now)
        self._battery = Battery(config, now)
        self._people_detector = PeopleDetector(config.lidar_range, config.lidar_fov)
        self.wifi = WirelessCard(world, seed)
        self._faults: set[str] = set()
        self._push = Twist()
        self._push_left = 0.0
        self._accel = 0.0
        self._command = Twist()
        self._estop = False
        self._collisions: list[Collision] = []
        self._in_contact = False
        self._scan: LaserScan | None = None
        self._scan_period = 1.0 / config.lidar_rate
        self._imu_period = 1.0 / config.imu_rate
        self._next_scan = now
        self._next_imu = now
        self._wall_gap = self._check_placement(self._floor, pose)
        self._plate_gap = self._plate_clearance(self._floor, pose)
        self.robot = SimRobot(self)
        scene.add(self)
        log.info("simulation of world %r: %s on %s at %s, seed %d", world.name, name, self._floor,
                 pose, seed)

    # -- what the world looks like ------------------------------------------------------------

    @property
    def floor(self) -> str:
        """Name of the floor the robot is on."""
        return self._floor

    @property
    def scene(self) -> Scene:
        """The world, clock and people this robot shares with the other robots in it."""
        return self._scene

    @property
    def true_pose(self) -> Pose2D:
        """Ground-truth pose on the current floor's map."""
        return self._base.pose

    @property
    def true_twist(self) -> Twist:
        """Ground-truth velocity of the base."""
        return self._base.twist

    @property
    def collisions(self) -> list[Collision]:
        """Every collision so far, oldest first (a copy)."""
        return list(self._collisions)

    @property
    def estop(self) -> bool:
        """True while the hardware e-stop button is pressed."""
        return self._estop

    @property
    def docked(self) -> bool:
        """True while the base stands still on a charger of its floor (contacts touch)."""
        return self._charger_touched() is not None

    @property
    def charger_current(self) -> bool:
        """True while a charger's current flows into the battery: docked, the data link's
        frames valid and the charger's mains on (:mod:`~polynav.robot.sim.charger`)."""
        return (self.docked and charger_faults.LINK_INVALID not in self._faults
                and charger_faults.NO_POWER not in self._faults)

    def dock_signals(self) -> DockSignals:
        """What the robot's docking sensors report now: the beacon of a charger on its floor
        seen, contact, and the data link's state."""
        pose = self._base.pose
        beacon = charger_faults.BEACON_OFF not in self._faults and any(
            c.beacon_seen(pose) for c in self._floors[self._floor].chargers)
        contact = self.docked
        if not contact:
            link = DockLink.NONE
        elif charger_faults.LINK_INVALID in self._faults:
            link = DockLink.INVALID
        else:
            link = DockLink.VALID
        return DockSignals(beacon=beacon, contact=contact, link=link)

    def _charger_touched(self) -> SimCharger | None:
        c = self.config
        twist = self._base.twist
        if twist.linear != 0.0 or twist.angular != 0.0:
            return None
        pose = self._base.pose
        for charger in self._floors[self._floor].chargers:
            if charger.touches(pose, c.dock_distance_tolerance, c.dock_heading_tolerance):
                return charger
        return None

    @property
    def odometry(self) -> Odometry:
        """The newest wheel odometry (every physics step), in the odometry frame: (0, 0, 0)
        where the body was created."""
        return self._odometry.reading

    @property
    def odometry_origin(self) -> Pose2D:
        """Where the odometry frame lies in the world: the true pose the body was created at,
        on its start floor (a teleport moves the body, not this frame)."""
        return self._odometry_origin

    def world_to_odometry(self, pose: Pose2D) -> Pose2D:
        """A world pose (start floor) expressed in the odometry frame as it was laid down,
        without the odometry's drift: what a goal given in world coordinates is, for a robot
        whose only frame is odometry's (navigation without a map)."""
        return pose.relative_to(self._odometry_origin)

    def odometry_to_world(self, pose: Pose2D) -> Pose2D:
        """The inverse of :meth:`world_to_odometry`."""
        return self._odometry_origin.compose(pose)

    @property
    def scan(self) -> LaserScan | None:
        """The newest lidar scan, or ``None`` before the first."""
        return self._scan

    @property
    def imu(self) -> ImuReading | None:
        """The newest IMU sample, or ``None`` before the first."""
        return self._imu.reading

    @property
    def battery(self) -> BatteryState:
        return self._battery.state

    def people_poses(self) -> tuple[Pose2D, ...]:
        """Where the people on the robot's floor are, heading where they walk (none if off)."""
        if not self._scene.people_enabled:
            return ()
        return tuple(p.pose for p in self._floors[self._floor].people)

    def wifi_scan(self) -> list[VisibleNetwork]:
        """The Wi-Fi networks the robot's card receives where it stands now."""
        state = self._floors[self._floor]
        pose = self._base.pose
        return self.wifi.scan(state.floor.level, pose.x, pose.y, state.occupied, state.info)

    def push(self, distance: float, speed: float = 0.3) -> None:
        """Push the robot by hand ``distance`` [m] straight ahead (negative: backwards) at
        ``speed`` [m/s], whatever it is commanded: its wheels roll, so odometry sees the
        motion, as when someone moves an e-stopped (free-wheeling) robot."""
        if not (math.isfinite(distance) and speed > 0.0):
            raise InvalidRequest("distance", "must be finite, with a speed > 0")
        self._push = Twist(math.copysign(speed, distance), 0.0)
        self._push_left = abs(distance) / speed

    def inject_fault(self, fault: str) -> None:
        """Break something, for tests and demos: ``"laser_slot_object"`` puts an object into
        the lidar's slot (it then returns a few centimetres over a sector); the charger's
        ``"charger_beacon_off"``, ``"charger_link_invalid"`` and ``"charger_no_power"`` (see
        :mod:`~polynav.robot.sim.charger`).

        Raises:
            InvalidRequest: an unknown fault.
        """
        if fault not in FAULTS:
            raise InvalidRequest("fault", f"unknown fault {fault!r}; known: {sorted(FAULTS)}")
        self._faults.add(fault)
        log.warning("fault injected: %s", fault)

    def clear_fault(self, fault: str) -> None:
        """Undo :meth:`inject_fault` (nothing if the fault is not there)."""
        self._faults.discard(fault)

    def detect_people(self) -> list[PersonDetection]:
        """The people the robot's leg tracker sees now (robot frame, see
        :mod:`~polynav.robot.sim.people_detector`); none when the walkers are off."""
        state = self._floors[self._floor]
        people = [(p.x, p.y) for p in state.people] if self._scene.people_enabled else []
        return self._people_detector.detect(
            self.clock.now(), self._base.pose, people, state.occupied, state.info
        )

    def detect_signs(self) -> list[SignDetection]:
        """The "no entry" signs the robot's sign camera sees now (robot frame, see
        :mod:`~polynav.robot.sim.sign_camera`); none for a robot without one."""
        config = self.config
        if config.sign_camera_range <= 0.0 or config.sign_camera_fov <= 0.0:
            return []
        state = self._floors[self._floor]
        return seen_signs(self._base.pose, state.floor.signs, reach=config.sign_camera_range,
                          fov=config.sign_camera_fov, occupied=state.occupied, info=state.info)

    # -- operator and test controls ------------------------------------------------------------

    def press_estop(self) -> None:
        """Press the e-stop: drive commands are dropped and the base brakes to a stand-still."""
        if not self._estop:
            log.info("e-stop pressed at t=%.3f", self.clock.now())
        self._estop = True
        self._command = Twist()

    def release_estop(self) -> None:
        """Release the e-stop; the base stays at rest until the next drive command."""
        if self._estop:
            log.info("e-stop released at t=%.3f", self.clock.now())
        self._estop = False

    def set_people(self, enabled: bool) -> None:
        """Let the walkers walk, or take them out of the world (they resume where they were);
        for every robot in the scene."""
        self._scene.people_enabled = enabled

    def teleport(self, floor: str, pose: Pose2D) -> None:
        """Move the robot to ``pose`` on ``floor``, at rest (a lift ride).

        Odometry and the IMU do not notice; a fresh scan is taken at once, so the newest scan
        shows the new surroundings.

        Raises:
            InvalidRequest: unknown floor, or the pose overlaps a wall there.
        """
        name = self.world.floor(floor).name
        self._wall_gap = self._check_placement(name, pose)
        self._plate_gap = self._plate_clearance(name, pose)
        self._floor = name
        self._base.place(pose)
        self._scene.carts.follow(self.name, name, pose)
        self._in_contact = False
        now = self.clock.now()
        self._take_scan(now)
        self._next_scan = now + self._scan_period
        log.info("teleported to %s at %s", name, pose)

    def place_obstacle(self, floor: str, x: float, y: float, radius: float) -> None:
        """Put a round obstacle (a trolley left in a corridor) into ``floor``'s ground truth at
        (x, y) [m]: the lidar sees it and the base collides with it; the site map knows nothing.
        """
        state = self._floors[self.world.floor(floor).name]
        info = state.info
        ix, iy = info.world_to_cell(x, y)
        reach = int(math.ceil(radius / info.resolution))
        ys, xs = np.mgrid[iy - reach:iy + reach + 1, ix - reach:ix + reach + 1]
        cx = info.origin.x + (xs + 0.5) * info.resolution  # the origin has zero yaw (checked)
        cy = info.origin.y + (ys + 0.5) * info.resolution
        inside = (np.hypot(cx - x, cy - y) <= radius) & (xs >= 0) & (ys >= 0)
        inside &= (xs < info.width) & (ys < info.height)
        state.occupied[ys[inside], xs[inside]] = True
        log.info("obstacle of radius %.2f m placed at (%.2f, %.2f) on %s", radius, x, y, floor)

    def drive(self, command: Twist) -> None:
        """Command a body velocity (clamped to the limits); ignored while the e-stop is pressed."""
        if not self._estop:
            self._command = self._base.clamp(command)

    # -- time ----------------------------------------------------------------------------------

    @property
    def physics_period(self) -> float:
        """Simulated seconds per :meth:`step`."""
        return self.config.physics_period

    def step(self, dt: float | None = None) -> None:
        """Advance the scene one physics period, or ``dt`` [s] in equal steps no longer than one
        period (every robot in the scene moves).

        Raises:
            InvalidRequest: ``dt`` is not positive.
        """
        self._scene.step(dt)

    def _move(self, h: float, now: float, people: npt.NDArray[np.float64],
              robots: npt.NDArray[np.float64]) -> None:
        """The body's part of a scene step before the clock moves: drive, collide, odometry,
        IMU and battery (``people`` and ``robots``: (K, 3) discs on its floor)."""
        c = self.config
        here = self._floors[self._floor]
        base = self._base
        v_before = base.twist.linear
        if self._push_left > 0.0:
            # Pushed by hand: the wheels roll free (as under the e-stop), odometry counts it.
            self._push_left -= h
            command = self._push
        else:
            command = Twist() if self._estop else self._command
        step = base.propose(command, h)
        distance, rotation = step.distance, step.rotation
        if distance != 0.0 or rotation != 0.0:
            hit, wall, plate = self._obstacle_hit(here, step.pose, people, robots)
            if hit is None:
                base.apply(step)
                # The gaps the check just measured at the pose now taken (nothing changed
                # between): the new wall and plate gaps.
                self._wall_gap, self._plate_gap = wall, plate
            else:
                base.halt()
                distance = rotation = 0.0
                if not self._in_contact:
                    self._collisions.append(Collision(now, base.pose, hit))
                    log.warning("%s: collision with a %s at t=%.3f, %s", self.name, hit, now,
                                base.pose)
                self._in_contact = True
        else:
            base.apply(step)  # a standing base stays put; its velocity may still change
        if self._in_contact and min(
            self._wall_gap, self._plate_gap, self._legs_clearance(base.pose),
            person_clearance(base.pose.x, base.pose.y, c.robot_radius, people),
            person_clearance(base.pose.x, base.pose.y, c.robot_radius, robots),
        ) >= c.collision_release_distance:
            self._in_contact = False

        self._odometry.update(distance, rotation, h, now)
        self._imu.accumulate(rotation)
        travel = abs(distance) + c.robot_radius * abs(rotation)
        self._battery.update(h, travel, charging=self.charger_current, stamp=now)
        self._accel = (base.twist.linear - v_before) / h

    def _sense(self, now: float, people: npt.NDArray[np.float64],
               robots: npt.NDArray[np.float64]) -> None:
        """The body's part of a scene step once the clock has moved: IMU and lidar when due."""
        if now >= self._next_imu - _EPS:
            self._imu.sample(self._base.twist.angular, self._accel, now)
            self._next_imu = _next_due(self._next_imu, self._imu_period, now)
        if self.scan_due(now):
            self._take_scan(now, people, robots)
            self._next_scan = _next_due(self._next_scan, self._scan_period, now)

    def scan_due(self, now: float) -> bool:
        """Whether :meth:`_sense` at ``now`` takes a scan (the only use of its ``robots``)."""
        return now >= self._next_scan - _EPS

    # -- internals ------------------------------------------------------------------------------

    def _obstacle_hit(
        self, here: FloorState, pose: Pose2D, people: npt.NDArray[np.float64],
        robots: npt.NDArray[np.float64],
    ) -> tuple[Obstacle | None, float, float]:
        """What a move to ``pose`` would newly overlap, if anything, with the wall and plate
        gaps measured there (NaN where the check stopped before measuring).

        Moving while overlapping (after a teleport into a tight spot) is allowed as long as the
        overlap does not deepen, so the robot can always back out.
        """
        c = self.config
        r = c.robot_radius
        wall = body_wall_clearance(here.occupied, here.info, pose, radius=r,
                                   polygon=c.footprint_polygon,
                                   horizon=c.collision_release_distance)
        if wall < 0.0 and wall < self._wall_gap - _EPS:
            return "wall", wall, math.nan
        plate = self._plate_clearance(self._floor, pose)  # a charger's plate: a wall too
        if plate < 0.0 and plate < self._plate_gap - _EPS:
            return "wall", wall, plate
        legs = self._legs_clearance(pose)  # carts' legs, and the legs of the load carried
        if legs < 0.0 and legs < self._legs_clearance(self._base.pose) - _EPS:
            return "wall", wall, plate
        checks: tuple[tuple[npt.NDArray[np.float64], Obstacle], ...] = (
            (people, "person"), (robots, "robot"))
        for circles, kind in checks:
            if circles.shape[0] and _may_touch(pose.x, pose.y, r, circles):
                gap = person_clearance(pose.x, pose.y, r, circles)
                if gap < 0.0:
                    old = person_clearance(self._base.pose.x, self._base.pose.y, r, circles)
                    if gap < old - _EPS:
                        return kind, wall, plate
        return None, wall, plate

    def _take_scan(self, now: float, people: npt.NDArray[np.float64] | None = None,
                   robots: npt.NDArray[np.float64] | None = None) -> None:
        here = self._floors[self._floor]
        if people is None:
            people = self._scene.people_circles(self._floor)
        if robots is None:
            robots = self._scene.robots_near(self)
        circles = np.concatenate((people, robots)) if robots.shape[0] else people
        legs = self._scene.carts.legs(self._floor, mask=self.name)
        if legs.shape[0]:
            circles = np.concatenate((circles, legs))
        scan = self._lidar.scan(here.occupied, here.info, self._base.pose, circles, now,
                                self._plates_in_reach(here))
        if LASER_SLOT_OBJECT in self._faults:
            scan = _blocked_slot(scan)
        self._scan = scan

    def _plates_in_reach(self, here: FloorState) -> npt.NDArray[np.float64]:
        """The chargers' plate segments on ``here`` the lidar may reach from where the body
        stands. The others lie beyond the range by a metre or more, so every beam's hit on
        them would be dropped as out of range anyway: leaving them out changes no return,
        and spares the beams-by-segments arithmetic on most scans."""
        if not here.chargers:
            return here.charger_segments
        c, pose = self.config, self._base.pose
        reach = c.lidar_range + math.hypot(c.lidar_x, c.lidar_y) + 1.0
        near = [ch.segments for ch in here.chargers
                if math.hypot(ch.face.x - pose.x, ch.face.y - pose.y) <= reach + ch.extent]
        if len(near) == len(here.chargers):
            return here.charger_segments
        return np.concatenate(near) if near else _NO_SEGMENTS

    def _legs_clearance(self, pose: Pose2D) -> float:
        """Gap [m] between the body at ``pose`` and the carts' legs on its floor (its own
        load's aside), and between its load's legs there and the walls."""
        c, here = self.config, self._floors[self._floor]
        return self._scene.carts.clearance(
            self.name, self._floor, pose, c.robot_radius, c.footprint_polygon,
            lambda x, y, r: body_wall_clearance(here.occupied, here.info, Pose2D(x, y),
                                                radius=r, horizon=c.collision_release_distance))

    # -- loads (carts and cabins) ---------------------------------------------------------------

    @property
    def load(self) -> SimCart | None:
        """The cart or cabin the robot carries, if any."""
        return self._scene.carts.carried_by(self.name)

    def set_jack_height(self, height: float) -> SimCart | None:
        """The jacking axis now stands at ``height`` [m]: raised under a cart it lifts it,
        lowered it sets it down (:meth:`~polynav.robot.sim.carts.CartYard.jack`)."""
        return self._scene.carts.jack(self.name, self._floor, self._base.pose, height)

    def cabin_tag(self) -> str | None:
        """What the latch's tag reader reads: the id of the cabin the robot stands in
        (aligned), or of the one it carries; None with no cabin there."""
        load = self.load
        if load is None:
            load = self._scene.carts.under(self.name, self._floor, self._base.pose,
                                           CartKind.CABIN)
        if load is None or load.spec.kind is not CartKind.CABIN:
            return None
        return load.spec.cabin_id

    def latch(self) -> SimCart:
        """Close the latch on the cabin the robot stands in.

        Raises:
            Conflict: no cabin there (or the robot carries something already).
        """
        yard = self._scene.carts
        cabin = yard.under(self.name, self._floor, self._base.pose, CartKind.CABIN)
        if cabin is None:
            raise Conflict("the latch closed on nothing: no cabin around the robot")
        yard.take(cabin, self.name, self._base.pose)
        return cabin

    def unlatch(self) -> SimCart | None:
        """Open the latch: the cabin carried (if any) is left where it stands."""
        load = self.load
        if load is None or load.spec.kind is not CartKind.CABIN:
            return None
        return self._scene.carts.release(self.name)

    def _plate_clearance(self, floor: str, pose: Pose2D) -> float:
        c = self.config
        return body_clearance(pose, c.robot_radius, c.footprint_polygon,
                              self._floors[floor].chargers)

    def _default_pose(self, floor: str) -> Pose2D:
        if floor == self.world.start_floor:
            return self.world.start_pose
        for p in self.world.floor(floor).points:
            if p.kind is PointKind.INITIAL:
                return p.pose
        raise InvalidRequest("pose", f"floor {floor!r} has no initial point; give a pose")

    def _check_placement(self, floor: str, pose: Pose2D) -> float:
        here = self._floors[floor]
        c = self.config
        gap = body_wall_clearance(here.occupied, here.info, pose, radius=c.robot_radius,
                                  polygon=c.footprint_polygon,
                                  horizon=c.collision_release_distance)
        if gap < 0.0:
            raise InvalidRequest("pose", f"{pose} on {floor!r} overlaps a wall by {-gap:.3f} m")
        for other in self._scene.bodies:
            if other is not self and other.floor == floor and pose.distance_to(
                    other.true_pose) < c.robot_radius + other.config.robot_radius:
                raise InvalidRequest("pose", f"{pose} on {floor!r} overlaps robot {other.name!r}")
        return gap

def _may_touch(x: float, y: float, radius: float, circles: npt.NDArray[np.float64]) -> bool:
    """Whether a disk at (x, y) of ``radius`` may overlap one of ``circles`` ((K, 3) rows x, y,
    radius). False only when every circle is clear of it by a micrometre, far beyond rounding,
    so :func:`person_clearance` is then surely >= 0: a few float operations per circle spare
    the array arithmetic when no one is near, as on most steps."""
    for cx, cy, cr in circles.tolist():
        dx, dy, reach = cx - x, cy - y, cr + radius + 1e-6
        if dx * dx + dy * dy <= reach * reach:
            return True
    return False


def _blocked_slot(scan: LaserScan) -> LaserScan:
    """The scan with the beams of a sector around straight ahead stopped a few centimetres out,
    as by an object stuck in the lidar's slot."""
    ranges = scan.ranges.copy()
    angles = scan.angles
    sector = np.abs(np.arctan2(np.sin(angles), np.cos(angles))) <= 0.5 * _SLOT_SECTOR
    ranges[sector] = np.float32(max(scan.range_min, 0.06))
    return dataclasses.replace(scan, ranges=ranges)


def _next_due(due: float, period: float, now: float) -> float:
    """The next sample time on the sensor's own grid, never in the past."""
    due += period
    if due <= now + _EPS:
        due = now + period
    return due
