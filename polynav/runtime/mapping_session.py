"""One mapping run: the SLAM service fed the robot's scans and odometry on the runtime's clock.

The runtime owns a :class:`MappingSession` while in MAPPING mode. Each control period it hands
over the odometry and the newest scan (once); the session pairs the scan with the odometry pose
*at the scan's stamp*, interpolated between the odometry readings it kept (a scan is up to a
lidar period older than the tick that delivers it: at 0.6 rad/s, taking the tick's odometry
instead skewed every scan by ~3° while turning, and the map blurred). It keeps the robot's pose
on the map being built and renders the live map on demand, cached until new scans came in.
The map frame is the one the session starts in: when it starts from an existing map (``update``),
its first pose is where the robot is on that map, so the new map shares the old one's frame.
"""

from __future__ import annotations

import logging
import math
from collections import deque

import numpy as np

from polynav.geometry import Pose2D
from polynav.mapping.config import SlamConfig
from polynav.mapping.slam import Slam
from polynav.maps.map import Map, MapInfo
from polynav.robot.interface import LaserScan, Odometry
from polynav.runtime.mapping_area import MappedArea

log = logging.getLogger(__name__)

# Odometry readings kept to pair scans with (control ticks; a scan is at most a few old).
_ODOMETRY_KEPT = 16


class MappingSession:
    """Feeds :class:`~polynav.mapping.slam.Slam` and keeps the pose and the live map.

    Args:
        floor: the floor being mapped (the saved map belongs to it).
        start: the robot's pose in the frame of the new map (its first scan's pose).
        name: the map's name when it extends an existing map, else ``None``.
        prior: that map (its frame is the new map's; ``start`` is the robot's pose on it).
        config: the SLAM's parameters.
        started_at: when the session started [s, runtime clock].
    """

    def __init__(self, floor: str | None, start: Pose2D, *, name: str | None = None,
                 prior: Map | None = None, config: SlamConfig | None = None,
                 started_at: float = 0.0) -> None:
        self.floor = floor
        self.name = name
        self.started_at = started_at
        self._slam = Slam(config, prior=prior)
        self._area = MappedArea(self._slam.config, prior)
        self._start = start
        self._offset: Pose2D | None = None  # odometry frame -> map frame, from the first scan
        self._pose = start
        self._scan_pose = start
        self._scan_odom = Pose2D()
        self._last_stamp: float | None = None
        self._rendered: tuple[int, Map] | None = None
        self._odometry: deque[tuple[float, Pose2D]] = deque(maxlen=_ODOMETRY_KEPT)
        self.scans = 0

    @property
    def pose(self) -> Pose2D:
        """The robot's pose on the map being built."""
        return self._pose

    def tick(self, odometry: Odometry, scan: LaserScan | None) -> None:
        """Take the scan if it is new; otherwise carry the pose by odometry."""
        if self._offset is None:
            # The first odometry pose is the start pose: compose every later one onto it.
            self._offset = self._start.compose(odometry.pose.inverse())
        if not self._odometry or odometry.stamp > self._odometry[-1][0]:
            self._odometry.append((odometry.stamp, odometry.pose))
        if scan is None or scan.stamp == self._last_stamp:
            if self.scans:  # carry the last scan's estimate forward by odometry
                self._pose = self._pose_now(odometry.pose)
            return
        self._last_stamp = scan.stamp
        at_scan = self._odometry_at(scan.stamp)
        odom = self._offset.compose(at_scan)
        nodes = self._slam.node_count
        estimate = self._slam.add_scan(odom, scan.ranges, scan.angles, scan.stamp,
                                       sensor_pose=scan.sensor_pose)
        if self._slam.node_count != nodes:
            self._area.insert(estimate, scan)
        self._scan_odom = at_scan
        self._scan_pose = estimate
        self._pose = self._pose_now(odometry.pose)
        self.scans += 1

    def _pose_now(self, odom: Pose2D) -> Pose2D:
        """The last scan's estimate, advanced by the odometry since that scan."""
        return self._scan_pose.compose(odom.relative_to(self._scan_odom))

    def _odometry_at(self, stamp: float) -> Pose2D:
        """The odometry pose at ``stamp``: linear between the two readings around it, the
        nearest reading outside them."""
        kept = self._odometry
        if stamp <= kept[0][0]:
            return kept[0][1]
        for (t0, p0), (t1, p1) in zip(list(kept)[:-1], list(kept)[1:], strict=True):
            if t0 <= stamp <= t1:
                f = (stamp - t0) / (t1 - t0)
                dtheta = math.remainder(p1.theta - p0.theta, 2.0 * math.pi)
                return Pose2D(p0.x + f * (p1.x - p0.x), p0.y + f * (p1.y - p0.y),
                              p0.theta + f * dtheta)
        return kept[-1][1]

    def trajectory(self) -> list[Pose2D]:
        """The poses of the scans taken so far, on the map being built (optimised)."""
        return self._slam.trajectory()

    def live_map(self) -> Map:
        """The map so far (rendered again only after new scans)."""
        nodes = self._slam.node_count
        if self._rendered is None or self._rendered[0] != nodes:
            grid = self._slam.render_map() if nodes else None
            if grid is None or grid.info.width == 0 or grid.info.height == 0:
                # Nothing scanned yet: one unknown cell where the robot stands.
                resolution = self._slam.config.resolution
                origin = Pose2D(self._start.x - 0.5 * resolution, self._start.y - 0.5 * resolution)
                grid = Map(MapInfo(resolution, 1, 1, origin), np.full((1, 1), -1, dtype=np.int8))
            self._rendered = (nodes, grid)
        return self._rendered[1]

    def mapped_area(self, now: float) -> float:
        """Known cells x the cell's area [m²], counted at most once a second of the runtime's
        clock (:class:`~polynav.runtime.mapping_area.MappedArea`)."""
        return self._area.area(now)

    def finish(self) -> Map:
        """Optimise the whole graph once more and render the final map."""
        self._slam.finish()
        self._rendered = None
        grid = self.live_map()
        log.info("mapping finished: %d scans, %d nodes, %d loop closures", self.scans,
                 self._slam.node_count, self._slam.loop_closures)
        return grid
