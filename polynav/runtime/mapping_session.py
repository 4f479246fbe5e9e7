"""One mapping run: the SLAM service fed the robot's scans and odometry on the runtime's clock.

The runtime owns a :class:`MappingSession` while in MAPPING mode. Each control period it hands
over the newest scan (once) with the odometry pose of the moment; the session keeps the robot's
pose on the map being built and renders the live map on demand, cached until new scans came in.
The map frame is the one the session starts in: when it starts from an existing map (``update``),
its first pose is where the robot is on that map, so the new map shares the old one's frame.
"""

from __future__ import annotations

import logging

import numpy as np

from polynav.geometry import Pose2D
from polynav.mapping.config import SlamConfig
from polynav.mapping.slam import Slam
from polynav.maps.map import Map, MapInfo
from polynav.robot.interface import LaserScan, Odometry

log = logging.getLogger(__name__)


class MappingSession:
    """Feeds :class:`~polynav.mapping.slam.Slam` and keeps the pose and the live map.

    Args:
        floor: the floor being mapped (the saved map belongs to it).
        start: the robot's pose in the frame of the new map (its first scan's pose).
        name: the map's name when it extends an existing map, else ``None``.
    """

    def __init__(self, floor: str | None, start: Pose2D, *, name: str | None = None,
                 config: SlamConfig | None = None) -> None:
        self.floor = floor
        self.name = name
        self._slam = Slam(config)
        self._start = start
        self._offset: Pose2D | None = None  # odometry frame -> map frame, from the first scan
        self._pose = start
        self._last_stamp: float | None = None
        self._rendered: tuple[int, Map] | None = None
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
        if scan is None or scan.stamp == self._last_stamp:
            return
        self._last_stamp = scan.stamp
        odom = self._offset.compose(odometry.pose)
        estimate = self._slam.add_scan(odom, scan.ranges, scan.angles, scan.stamp,
                                       sensor_pose=scan.sensor_pose)
        self._pose = estimate
        self.scans += 1

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

    def finish(self) -> Map:
        """Optimise the whole graph once more and render the final map."""
        self._slam.finish()
        self._rendered = None
        grid = self.live_map()
        log.info("mapping finished: %d scans, %d nodes, %d loop closures", self.scans,
                 self._slam.node_count, self._slam.loop_closures)
        return grid
