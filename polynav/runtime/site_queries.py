"""Questions about the site and the navigation stack that dialects ask: how long is a path, where
near a point can the robot stand, how far is a point from obstacles, which path is it following.

Each is answered on the real maps and costmaps: the live costmap (static map, keepouts, what the
lidar sees, inflation) for the map navigation runs on, and a costmap built from the stored map
and its keepouts for any other map (cached until that map or its keepouts change). Live state is
read between the runtime's ticks (:meth:`RobotRuntime.run_between_ticks`), so a query never sees
a half-updated costmap.
"""

from __future__ import annotations

import logging
import math
import threading
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from polynav.errors import Conflict
from polynav.geometry import Pose2D
from polynav.maps import costs as cost_values
from polynav.maps.costmap import Costmap, CostSnapshot
from polynav.maps.map import MapInfo
from polynav.planning.errors import NoPath, StartOccupied
from polynav.planning.grid_planner import GridPlanner
from polynav.robot.interface import LaserScan

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

MAX_PATH_POINTS = 2000
ACCESSIBLE_SEARCH_RADIUS = 3.0
"""How far [m] from the asked point a reachable place is looked for."""


@dataclass(frozen=True, slots=True)
class Distances:
    """From a point: to the nearest obstacle the lidar sees now (``None``: the point is out of
    the lidar's reach, or it sees nothing), and to the nearest obstacle of the static map."""

    sensed: float | None
    static: float


class SiteQueries:
    """The queries of one runtime (``runtime.queries``), with the per-map costmaps and distance
    fields they build cached."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime
        self._lock = threading.Lock()
        self._costmaps: dict[str, tuple[object, CostSnapshot]] = {}
        self._static_distance: dict[str, tuple[object, MapInfo, npt.NDArray[np.float32]]] = {}

    # -- path length ---------------------------------------------------------------------------

    def path_length(self, map_name: str, start: Pose2D, goal: Pose2D) -> float:
        """Length [m] of the path polynav would plan from ``start`` to ``goal`` on ``map_name``.

        On the map navigation runs on, the live costmap is used (what blocks the robot now
        blocks the plan); on another map, its stored map and keepouts.

        Raises:
            NotFound: unknown map.
            PlanningError: no path (start or goal outside the map or in an obstacle, or walled
                off); see :mod:`polynav.planning.errors`.
        """
        grid = self._costs(map_name)
        planner = GridPlanner(self._runtime.stack_config().planner)
        return planner.plan(grid, start, goal).length

    def _costs(self, map_name: str) -> CostSnapshot:
        runtime = self._runtime

        def live() -> CostSnapshot | None:
            stack = runtime.navigation_stack
            if stack is None or runtime.map_name != map_name:
                return None
            return stack.costmap.snapshot()

        snapshot = runtime.run_between_ticks(live)
        if snapshot is not None:
            return snapshot
        store = runtime.store
        record = store.map_record(map_name)
        keepouts = tuple(store.keepouts(map_name))
        version = (record, keepouts)
        with self._lock:
            cached = self._costmaps.get(map_name)
            if cached is not None and cached[0] == version:
                return cached[1]
        costmap = Costmap.from_map(store.load_map(map_name), runtime.stack_config().costmap)
        if keepouts:
            costmap.set_keepouts(keepouts)
        snapshot = costmap.snapshot()
        with self._lock:
            self._costmaps[map_name] = (version, snapshot)
        return snapshot

    # -- the current plan ----------------------------------------------------------------------

    def planned_path(self, max_points: int = MAX_PATH_POINTS) -> list[tuple[float, float]]:
        """The global path of the running goal, map frame, at most ``max_points`` points
        (evenly spaced along it when it has more); empty when no goal runs."""
        runtime = self._runtime

        def read() -> npt.NDArray[np.float64] | None:
            stack = runtime.navigation_stack
            if stack is None or runtime.status().navigation_state != "running":
                return None
            path = stack.navigator.path
            return None if path is None else path.points.copy()

        points = runtime.run_between_ticks(read)
        if points is None or points.shape[0] == 0:
            return []
        return [(float(x), float(y)) for x, y in resample(points, max_points)]

    # -- free space near a point ---------------------------------------------------------------

    def accessible_point(
        self, x: float, y: float, radius: float = ACCESSIBLE_SEARCH_RADIUS
    ) -> tuple[float, float]:
        """The place nearest (x, y) within ``radius`` [m] where the robot fits on the live
        costmap and which it can reach from where it stands; (x, y) itself when it is one.

        Raises:
            Conflict: not navigating.
            NoPath: no such place within ``radius``.
            StartOccupied: the robot has no free space around it.
        """
        runtime = self._runtime

        def read() -> tuple[CostSnapshot, Pose2D]:
            stack = runtime.navigation_stack
            if stack is None:
                raise Conflict("not navigating: start navigation first")
            return stack.costmap.snapshot(), stack.estimate.pose

        grid, pose = runtime.run_between_ticks(read)
        info, costs = grid.info, grid.costs
        passable = costs < cost_values.INSCRIBED
        labels, _ = ndimage.label(passable, structure=np.ones((3, 3), dtype=bool))
        robot_label = _label_near(labels, info, pose.x, pose.y)
        if robot_label == 0:
            raise StartOccupied("no free space around the robot to reach anything from")
        reachable = labels == robot_label
        ix, iy = info.world_to_cell(x, y)
        if 0 <= ix < info.width and 0 <= iy < info.height and reachable[iy, ix]:
            return (x, y)
        reach = int(math.ceil(radius / info.resolution))
        x0, x1 = max(0, ix - reach), min(info.width, ix + reach + 1)
        y0, y1 = max(0, iy - reach), min(info.height, iy + reach + 1)
        if x0 >= x1 or y0 >= y1:
            raise NoPath(f"no reachable place within {radius:g} m of ({x:g}, {y:g})")
        ys, xs = np.nonzero(reachable[y0:y1, x0:x1])
        if xs.size == 0:
            raise NoPath(f"no reachable place within {radius:g} m of ({x:g}, {y:g})")
        cx = info.origin.x + (xs + x0 + 0.5) * info.resolution
        cy = info.origin.y + (ys + y0 + 0.5) * info.resolution
        distance = np.hypot(cx - x, cy - y)
        best = int(np.argmin(distance))
        if distance[best] > radius:
            raise NoPath(f"no reachable place within {radius:g} m of ({x:g}, {y:g})")
        return (float(cx[best]), float(cy[best]))

    # -- distances to obstacles ----------------------------------------------------------------

    def distances(self, x: float, y: float) -> Distances:
        """How far (x, y) is from what the lidar sees now and from the static map's obstacles.

        Raises:
            Conflict: not navigating.
        """
        runtime = self._runtime

        def read() -> tuple[str, Pose2D, LaserScan | None]:
            stack = runtime.navigation_stack
            name = runtime.map_name
            if stack is None or name is None:
                raise Conflict("not navigating: start navigation first")
            return name, stack.estimate.pose, runtime.robot.read_scan()

        map_name, pose, scan = runtime.run_between_ticks(read)
        static = self._static_distance_at(map_name, x, y)
        sensed: float | None = None
        if scan is not None and math.hypot(x - pose.x, y - pose.y) <= scan.range_max:
            hits = scan_points(scan, pose)
            if hits.shape[0]:
                sensed = float(np.min(np.hypot(hits[:, 0] - x, hits[:, 1] - y)))
        return Distances(sensed, static)

    def _static_distance_at(self, map_name: str, x: float, y: float) -> float:
        store = self._runtime.store
        record = store.map_record(map_name)
        with self._lock:
            cached = self._static_distance.get(map_name)
        if cached is None or cached[0] != record:
            grid = store.load_map(map_name)
            field = ndimage.distance_transform_edt(~grid.occupied()).astype(np.float32)
            field *= np.float32(grid.info.resolution)
            cached = (record, grid.info, field)
            with self._lock:
                self._static_distance[map_name] = cached
        _, info, field = cached
        ix, iy = info.world_to_cell(x, y)
        if not info.contains(ix, iy):
            return 0.0  # outside the map counts as an obstacle (as on the costmap)
        return float(field[iy, ix])


def resample(points: npt.NDArray[np.float64], count: int) -> npt.NDArray[np.float64]:
    """``points`` itself when it has at most ``count`` points, else ``count`` points evenly
    spaced along the polyline, first and last kept."""
    if points.shape[0] <= count:
        return points
    steps = np.hypot(*np.diff(points, axis=0).T)
    along = np.concatenate([[0.0], np.cumsum(steps)])
    wanted = np.linspace(0.0, along[-1], count)
    return np.column_stack([np.interp(wanted, along, points[:, 0]),
                            np.interp(wanted, along, points[:, 1])])


def scan_points(scan: LaserScan, pose: Pose2D) -> npt.NDArray[np.float64]:
    """The scan's returns as (N, 2) map-frame points, seen from ``pose`` (the robot's)."""
    ranges = scan.ranges.astype(np.float64)
    valid = np.isfinite(ranges) & (ranges >= scan.range_min) & (ranges <= scan.range_max)
    sensor = scan.sensor_pose
    angles = scan.angles[valid] + sensor.theta
    r = ranges[valid]
    sx = sensor.x + r * np.cos(angles)
    sy = sensor.y + r * np.sin(angles)
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    return np.column_stack([pose.x + c * sx - s * sy, pose.y + s * sx + c * sy])


def _label_near(
    labels: npt.NDArray[np.signedinteger[Any]], info: MapInfo, x: float, y: float
) -> int:
    """The free-space component at (x, y), or the nearest one within 0.5 m (the robot may stand
    in the inflated margin of a wall)."""
    ix, iy = info.world_to_cell(x, y)
    reach = int(math.ceil(0.5 / info.resolution))
    x0, x1 = max(0, ix - reach), min(info.width, ix + reach + 1)
    y0, y1 = max(0, iy - reach), min(info.height, iy + reach + 1)
    if x0 >= x1 or y0 >= y1:
        return 0
    window = labels[y0:y1, x0:x1]
    ys, xs = np.nonzero(window)
    if xs.size == 0:
        return 0
    nearest = int(np.argmin(np.hypot(xs + x0 - ix, ys + y0 - iy)))
    return int(window[ys[nearest], xs[nearest]])
