"""Navigation without a prior map: goals in the odometry frame, a rolling costmap from the lidar.

A user in a new building says "10 m ahead" before any map exists. The stack then has:

* **a frame**: the odometry frame the robot started in; goals are poses in it, and the pose is
  odometry + IMU corrected by matching each scan to the robot's own recent scans
  (:class:`~polynav.localization.odometry_frame.OdometryFrameLocalizer`);
* **a rolling window** for the costmap: a square of unknown space around the robot (and the
  goal, when one is given) that only the lidar fills in, marking what it hits and clearing what
  it sees through. Unknown space may be planned through at a cost (the planner prices it as the
  dearest passable cell, so known free floor is preferred) and is not an obstacle to the
  controller, which stops only for what the lidar marked. When the robot nears the window's
  edge, the window is drawn again around it (:meth:`MaplessStack.tick`); marks outside the
  lidar's view are forgotten then, as any rolling window forgets (Nav2's ``rolling_window``),
  and seen again as soon as the robot looks;
* **the same navigator, goal options and events** as with a map: only the frame and the
  costmap's source differ.

The people layer is left out: its grid cannot follow a rolling window (a known limit, noted in
docs/decisions.md); people are still marked by the lidar as obstacles.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field, replace

import numpy as np

from polynav.errors import ConfigError, check_positive
from polynav.geometry import Pose2D, Twist
from polynav.localization.odometry_frame import OdometryFrameConfig, OdometryFrameLocalizer
from polynav.maps.map import Map, MapInfo
from polynav.nav.attempt import GoalOptions
from polynav.nav.navigator import EventSink
from polynav.nav.stack import NavigationStack, StackConfig
from polynav.robot.interface import Robot

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class MaplessConfig:
    """The rolling window and the localizer of navigation without a map.

    Attributes:
        window: side of the square window [m] around the robot; grown to hold a far goal.
        resolution: its cell size [m].
        edge_margin: the window is drawn again around the robot when it comes this close [m]
            to an edge (and holds no running goal's path to the far side).
        goal_margin: a goal lies at least this far [m] inside the window.
        max_window: the window never grows beyond this side [m] (a goal farther away fails
            as off the map, rather than a grid of hundreds of megabytes).
        localization: the odometry-frame localizer's settings.
    """

    window: float = 30.0
    resolution: float = 0.05
    edge_margin: float = 6.0
    goal_margin: float = 5.0
    max_window: float = 200.0
    localization: OdometryFrameConfig = field(default_factory=OdometryFrameConfig)

    def __post_init__(self) -> None:
        check_positive(self, "mapless.", ("window", "resolution", "edge_margin", "goal_margin",
                                          "max_window"))
        if self.window > self.max_window:
            raise ConfigError("mapless.window", f"must be <= max_window ({self.max_window:g})")
        if 2.0 * self.edge_margin >= self.window:
            raise ConfigError("mapless.edge_margin", "must be below half the window")


MAPLESS_CLEARANCE_TIME = 0.15
"""[s] the controller's ``clearance_time`` without a map, at least: the pace with a map. It was
0.25 s while nothing else kept the robot from meeting an unseen wall round a corner at 2 m/s
(lattice course 33); now the controller drives no faster than it can stop on the floor it has
seen (``PurePursuitConfig.sight_latency``), which is the cause addressed, and the slower
clearance pace only cost time past every post (research-base, 100 lattice courses without a
map: 3.24x -> 2.87x optimal, 0 collisions)."""


def mapless_stack_config(base: StackConfig | None = None) -> StackConfig:
    """``base`` made for unknown space: the costmap tracks it, the planner crosses it at a
    cost, the controller keeps a slower pace near obstacles (``MAPLESS_CLEARANCE_TIME``), and
    the people layer (which cannot roll with the window) is off."""
    base = base or StackConfig()
    controller = base.controller
    return replace(
        base,
        costmap=replace(base.costmap, track_unknown=True),
        planner=replace(base.planner, allow_unknown=True),
        controller=replace(controller, clearance_time=max(controller.clearance_time,
                                                          MAPLESS_CLEARANCE_TIME)),
        people=replace(base.people, enabled=False),
    )


def unknown_window(centre_x: float, centre_y: float, side: float, resolution: float) -> Map:
    """An all-unknown map ``side`` metres square centred on (x, y), cells aligned to the
    resolution grid of the odometry frame (so that re-drawn windows share cell boundaries)."""
    cells = max(1, int(math.ceil(side / resolution)))
    ox = math.floor((centre_x - 0.5 * side) / resolution) * resolution
    oy = math.floor((centre_y - 0.5 * side) / resolution) * resolution
    data = np.full((cells, cells), -1, dtype=np.int8)
    return Map(MapInfo(resolution, cells, cells, Pose2D(ox, oy)), data)


class MaplessStack(NavigationStack):
    """A navigation stack that needs no map (see the module docstring).

    Args:
        robot: the robot backend.
        config: the stack's configuration (made mapless with :func:`mapless_stack_config`).
        mapless: the window and localizer settings.
        on_event: navigator events, as for :class:`NavigationStack`.
    """

    def __init__(
        self,
        robot: Robot,
        *,
        config: StackConfig | None = None,
        mapless: MaplessConfig | None = None,
        on_event: EventSink | None = None,
    ) -> None:
        self.mapless = mapless or MaplessConfig()
        start = robot.read_odometry().pose
        grid = unknown_window(start.x, start.y, self.mapless.window, self.mapless.resolution)
        super().__init__(
            robot,
            grid,
            config=mapless_stack_config(config),
            on_event=on_event,
            localizer=OdometryFrameLocalizer(self.mapless.localization),
        )
        self._goal: Pose2D | None = None
        self.recentred = 0

    def go_to(self, goal: Pose2D, now: float, options: GoalOptions | None = None) -> int:
        """Start navigating to ``goal``, a pose in the odometry frame; the window is drawn to
        hold both the robot and the goal first."""
        self._goal = goal
        self._fit(self.estimate.pose, goal)
        return super().go_to(goal, now, options)

    def tick(self, now: float) -> Twist:
        """One control period (as :meth:`NavigationStack.tick`), then roll the window if the
        robot nears its edge."""
        command = super().tick(now)
        pose = self.estimate.pose
        info = self.costmap.info
        margin = self.mapless.edge_margin
        x0, y0 = info.origin.x, info.origin.y
        x1, y1 = x0 + info.width * info.resolution, y0 + info.height * info.resolution
        if min(pose.x - x0, x1 - pose.x, pose.y - y0, y1 - pose.y) < margin:
            running = self._goal if not self.navigator.state.finished else None
            self._fit(pose, running)
        return command

    def _fit(self, pose: Pose2D, goal: Pose2D | None) -> None:
        """Draw the window around ``pose`` (and ``goal``) unless it already holds them."""
        m = self.mapless
        points = [(pose.x, pose.y)] if goal is None else [(pose.x, pose.y), (goal.x, goal.y)]
        info = self.costmap.info
        x0, y0 = info.origin.x, info.origin.y
        x1, y1 = x0 + info.width * info.resolution, y0 + info.height * info.resolution
        inside = all(
            x0 + m.edge_margin <= x <= x1 - m.edge_margin
            and y0 + m.edge_margin <= y <= y1 - m.edge_margin
            for x, y in points
        )
        if inside:
            return
        xs = [p[0] for p in points]
        ys = [p[1] for p in points]
        span = max(max(xs) - min(xs), max(ys) - min(ys)) + 2.0 * max(m.goal_margin, m.edge_margin)
        side = min(m.max_window, max(m.window, span))
        cx, cy = 0.5 * (min(xs) + max(xs)), 0.5 * (min(ys) + max(ys))
        grid = unknown_window(cx, cy, side, m.resolution)
        self.costmap.set_static_map(grid)
        self.map = grid
        scan = self.robot.read_scan()
        if scan is not None:  # the marks in view now, rather than none until the next scan
            self.costmap.update_scan(self.estimate.pose, scan)
        self.recentred += 1
        log.info("mapless: window %g m drawn around (%.1f, %.1f)", side, cx, cy)
