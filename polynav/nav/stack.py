"""One robot's navigation stack: localization, costmap and navigator wired to a Robot.

The stack is what the runtime ticks at the control rate. Each tick it reads the robot's sensors,
advances localization, marks a new scan and the people the leg tracker sees into the costmap,
lets the navigator decide, and commands the base. It never reads the clock itself (``now``
comes from the caller), so it runs the same on simulated time and on the wall clock.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field, replace

from polynav.control import regulation
from polynav.control.progress_checker import ProgressChecker, ProgressCheckerConfig
from polynav.control.pure_pursuit import PurePursuitConfig, RegulatedPurePursuit
from polynav.errors import ConfigError
from polynav.footprint import Footprint
from polynav.geometry import Pose2D, Twist
from polynav.localization.interface import LocalizationEstimate, Localizer
from polynav.localization.pose_tracker import PoseTracker, PoseTrackerConfig
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.maps.layers.people import PeopleLayer
from polynav.maps.map import Map
from polynav.nav.attempt import GoalOptions
from polynav.nav.navigator import EventSink, Navigator
from polynav.nav.navigator_config import NavigatorConfig
from polynav.nav.people import PeopleConfig, PeopleView
from polynav.planning import registry
from polynav.planning.footprint_planner import LatticeConfig
from polynav.planning.grid_planner import GridPlannerConfig
from polynav.robot.interface import Robot
from polynav.robot.profile import RobotProfile

log = logging.getLogger(__name__)


ROUTE_PADDINGS = (0.15, 0.05)
"""[m] the room a polygon body's route leaves it all round, the first of these that leaves a
route (``LatticeConfig.footprint_paddings``). The controller drives at the clearance it has over
``clearance_time``: 5 cm of room is 0.33 m/s, 15 cm is 1 m/s, so a route round a tight spot is
often the quicker (research-base, lattice courses: 2.36x -> 2.11x optimal with a map, 3.44x ->
2.95x without). The courses' own yardstick keeps the planner's default."""


@dataclass(frozen=True, slots=True)
class StackConfig:
    """Configuration of every component of the stack, plus the control rate [Hz].

    ``lattice`` sets a polygon body's route search (the room its routes leave it:
    ``ROUTE_PADDINGS``). ``footprint`` is the robot's body, which the controller and the
    recoveries check for collisions; ``None`` is a disk of the costmap's ``robot_radius``. While
    the robot stands
    still (waiting for a lift, a corridor or a person), the costmap takes a scan at most every
    ``standing_scan_period`` [s] (0: every scan): the scene changes no faster than people walk,
    and a fleet's waiting robots map a quarter of the scans. The costmap's inscribed
    radius may not be below the body's (a planner planning for a smaller robot sends the body
    into gaps it does not fit), as Nav2 derives it from the footprint.
    """

    control_rate: float = 20.0
    costmap: CostmapConfig = field(default_factory=CostmapConfig)
    planner: GridPlannerConfig = field(default_factory=GridPlannerConfig)
    lattice: LatticeConfig = field(
        default_factory=lambda: LatticeConfig(footprint_paddings=ROUTE_PADDINGS))
    controller: PurePursuitConfig = field(default_factory=PurePursuitConfig)
    progress: ProgressCheckerConfig = field(default_factory=ProgressCheckerConfig)
    navigator: NavigatorConfig = field(default_factory=NavigatorConfig)
    localization: PoseTrackerConfig = field(default_factory=PoseTrackerConfig)
    people: PeopleConfig = field(default_factory=PeopleConfig)
    footprint: Footprint | None = None
    standing_scan_period: float = 0.2

    def __post_init__(self) -> None:
        if not self.standing_scan_period >= 0.0:
            raise ConfigError("standing_scan_period", "must be >= 0")
        if self.footprint is not None and (
            self.costmap.robot_radius < self.footprint.inscribed_radius - 1e-9
        ):
            raise ConfigError(
                "costmap.robot_radius",
                f"{self.costmap.robot_radius:g} m is below the footprint's inscribed radius "
                f"({self.footprint.inscribed_radius:g} m): the planner would plan for a smaller "
                "robot than the body",
            )

    @property
    def body(self) -> Footprint:
        """The footprint the controller checks: ``footprint``, or the costmap's disk."""
        return self.footprint or Footprint.circle(self.costmap.robot_radius)


# Obstacles raise costs this far [m] beyond the body's circumscribed radius, so paths keep off
# walls by a margin even for a rectangle's corners.
INFLATION_MARGIN = 0.3

# A robot blind behind backs out of a pocket at most this far [m]: along the way it came, which
# was free, but where nothing that came in behind it since would be seen.
BLIND_BACKOUT = 0.5


# A disk's INSCRIBED band reaches this many cells beyond its radius (``CostmapConfig.
# inscribed_cell_margin``): the grid planner is a disk's only model of its body, and without the
# half cell it planned gaps that the controller, checking cells as squares, then stopped before
# (delivery on lattice courses without a map: a block, a wait and a turn round per gap). A
# polygon's planner checks the body itself.
DISK_CELL_MARGIN = 0.5


def stack_config_for(profile: RobotProfile, base: StackConfig | None = None) -> StackConfig:
    """``base`` (default: the defaults) built for ``profile``'s robot.

    The costmap's inscribed radius is the body's inscribed radius (a disk's half a cell more:
    ``DISK_CELL_MARGIN``) and inflation reaches at least
    ``INFLATION_MARGIN`` past its circumscribed radius (Nav2's convention: a centre nearer than
    the inscribed radius to an obstacle is certainly a collision, one nearer than the
    circumscribed radius possibly, depending on the heading). The controller drives at the
    profile's cruise speeds and accelerations, never above its limits. It reverses in a recovery
    only if the profile allows, and backs out of a pocket no farther than its rear is seen (at
    least ``BLIND_BACKOUT`` along its way in). Operator settings
    (:meth:`polynav.runtime.settings.RobotSettings.stack_config`) then apply on top.
    """
    base = base or StackConfig()
    cruise, limits = profile.cruise, profile.limits
    ctl = base.controller
    controller = replace(
        ctl,
        max_linear_velocity=cruise.linear_velocity,
        max_angular_velocity=cruise.angular_velocity,
        linear_acceleration=cruise.linear_acceleration,
        linear_deceleration=cruise.linear_deceleration,
        angular_acceleration=cruise.angular_acceleration,
        min_regulated_speed=min(ctl.min_regulated_speed, cruise.linear_velocity),
        min_approach_velocity=min(ctl.min_approach_velocity, cruise.linear_velocity),
        min_rotation_speed=min(ctl.min_rotation_speed, limits.max_angular_velocity),
    )
    cm = base.costmap
    costmap = replace(
        cm,
        robot_radius=profile.inscribed_radius,
        inscribed_cell_margin=DISK_CELL_MARGIN if profile.footprint.is_circle else 0.0,
        inflation_radius=max(cm.inflation_radius, profile.circumscribed_radius + INFLATION_MARGIN),
        range_noise=profile.lidar.noise,
    )
    nav = base.navigator
    # A block's place is looked for as far ahead as the controller stops for an obstacle at
    # its cruise speed, and half a metre beyond.
    stopping = regulation.stop_distance(
        controller.max_linear_velocity, deceleration=controller.linear_deceleration,
        lookahead_time=controller.collision_lookahead_time, minimum=controller.min_stop_distance)
    navigator = replace(
        nav,
        passage_look_ahead=max(nav.passage_look_ahead, stopping + 0.5),
        reverse_allowed=nav.reverse_allowed and profile.reverse.allowed,
        recovery_backout_distance=min(nav.recovery_backout_distance,
                                      max(profile.rear_view, BLIND_BACKOUT)),
        dock_plate=profile.charger.plate,
    )
    return replace(base, controller=controller, costmap=costmap, navigator=navigator,
                   footprint=profile.footprint)


class NavigationStack:
    """Localization + costmap + navigator for one robot on one map."""

    def __init__(
        self,
        robot: Robot,
        grid: Map,
        *,
        config: StackConfig | None = None,
        on_event: EventSink | None = None,
        localizer: Localizer | None = None,
    ) -> None:
        self.config = config or StackConfig()
        self.robot = robot
        self.map = grid
        # Scan-to-map tracking on ``grid`` unless another localizer is given (navigation
        # without a map localizes in the odometry frame, :mod:`polynav.nav.mapless`).
        self.localizer: Localizer = localizer or PoseTracker(self.config.localization)
        if localizer is None:
            self.localizer.set_map(grid)
        people = self.config.people
        self._people_layer = PeopleLayer(
            grid.info, radius=people.social_distance, cost=people.layer_cost
        )
        extra = (self._people_layer,) if people.enabled else ()
        self.costmap = Costmap(grid, self.config.costmap, extra_layers=extra)
        self.people = PeopleView()
        ctl = self.config.controller
        # Re-plans weigh routes by the time this controller takes over them: full speed with
        # the room of its clearance pace, its slowest regulated speed at the least.
        navigator_config = replace(
            self.config.navigator,
            route_open_clearance=ctl.max_linear_velocity * ctl.clearance_time,
            route_least_clearance=ctl.min_regulated_speed * ctl.clearance_time,
        )
        self.navigator = Navigator(
            self.costmap,
            registry.for_footprint(self.config.body, self.config.planner, self.config.lattice),
            RegulatedPurePursuit(self.config.controller, footprint=self.config.body),
            ProgressChecker(self.config.progress),
            config=navigator_config,
            robot_radius=self.config.costmap.robot_radius,
            footprint=self.config.body,
            people=people,
            on_event=on_event,
        )
        self.software_estop = False
        self._last_scan_stamp: float | None = None
        self._costmap_scan_stamp = -math.inf
        self._command = Twist()

    @property
    def estimate(self) -> LocalizationEstimate:
        return self.localizer.estimate

    @property
    def command(self) -> Twist:
        """The velocity commanded at the last tick."""
        return self._command

    def _skip_scan(self, stamp: float, velocity: Twist) -> bool:
        """Standing still, with a scan in the costmap less than ``standing_scan_period`` old."""
        standing = (abs(velocity.linear) < 1e-3 and abs(velocity.angular) < 1e-3
                    and self._command.linear == 0.0 and self._command.angular == 0.0)
        return standing and stamp - self._costmap_scan_stamp < self.config.standing_scan_period

    def initialize(self, pose: Pose2D, now: float) -> None:
        """Tell localization roughly where the robot is (it refines the pose itself)."""
        self.localizer.initialize(pose, now)

    def go_to(self, goal: Pose2D, now: float, options: GoalOptions | None = None) -> int:
        """Start navigating to ``goal``; returns the attempt id."""
        return self.navigator.start(goal, now, options)

    def tick(self, now: float) -> Twist:
        """One control period: sense, localize, map obstacles, decide, command."""
        odometry = self.robot.read_odometry()
        scan = self.robot.read_scan()
        if scan is not None and scan.stamp == self._last_scan_stamp:
            scan = None
        estimate = self.localizer.update(odometry, self.robot.read_imu(), scan, now)
        people = self.config.people
        if people.enabled:
            self.people = PeopleView.from_detections(self.robot.read_people(), estimate.pose)
            self._people_layer.set_people(
                self.people.positions(people.horizon, people.prediction_step)
            )
        if scan is not None:
            self._last_scan_stamp = scan.stamp
        if scan is not None and not self._skip_scan(scan.stamp, odometry.twist):
            self._costmap_scan_stamp = scan.stamp
            self.costmap.update_scan(estimate.pose, scan)  # recomposes the people layer too
        elif people.enabled:
            self.costmap.update()
        estop = self.software_estop or self.robot.estop_pressed()
        charging = self.robot.read_battery().charging
        self._command = self.navigator.tick(
            now, estimate, odometry.twist, estop, charging=charging, people=self.people,
            scan=scan, dock=self.robot.read_dock(),
        )
        if estop:
            self._command = Twist()
        self.robot.drive(self._command)
        return self._command
