"""Localization with no prior map: the pose in the odometry frame, kept honest by the lidar.

Wheel odometry drifts: a few per cent of the distance and, worse, heading error that bends every
metre after it. Without a map to match against, the robot's own recent scans are the reference
(Cartographer's local SLAM): each scan is matched against a submap built from the scans before
it (:class:`~polynav.mapping.slam.Slam`, a correlative search and a Gauss-Newton refinement), so
the pose stays where the walls and posts say it is, and only the slow drift of chained matches
is left. Between scans the pose is carried by odometry.

Its uncertainty (:class:`~polynav.localization.interface.PoseUncertainty`) is that slow drift
against the frame, which no map ever resets: it starts at the floor when anchored and grows with
the distance and turn driven since (``drift``, ``heading_drift``). A goal in the odometry frame far
from the anchor is honestly less certain than one near it.

The prediction fuses the IMU as :class:`~polynav.localization.pose_tracker.PoseTracker` does:
the wheels give the translation, the gyro the rotation (minus a bias learnt while the wheels
stand still), since wheel slip corrupts heading first. That fused odometry is what the SLAM
sees, so a scan in a featureless direction keeps the gyro's heading.

The frame is the odometry frame the robot started in (a simulated robot's coincides with the
world's at its start pose): goals given in it stay put however far the robot drives.
:meth:`OdometryFrameLocalizer.initialize` re-anchors it (the pose given becomes the current
pose; the local map restarts).
"""

from __future__ import annotations

import bisect
import logging
import math
from collections import deque
from dataclasses import dataclass, field

from polynav.geometry import Pose2D, angle_diff
from polynav.localization.interface import LocalizationEstimate, LocalizationState
from polynav.localization.uncertainty import PoseCovariance
from polynav.mapping.config import SlamConfig
from polynav.mapping.slam import Slam
from polynav.maps.map import Map
from polynav.robot.interface import ImuReading, LaserScan, Odometry

log = logging.getLogger(__name__)

_HISTORY_SECONDS = 1.0


@dataclass(frozen=True, slots=True)
class OdometryFrameConfig:
    """How the mapless localizer fuses and matches.

    Attributes:
        slam: the local SLAM's settings (its loop closure keeps a robot that comes back to
            where it was from drifting apart from itself).
        use_imu: take the rotation from the gyro rather than the wheels.
        gyro_bias_time_constant: the gyro bias estimate forgets evidence over this time [s].
        max_gyro_bias: the bias estimate is clamped to this [rad/s].
        drift: the position's uncertainty grows by this much per metre driven [m/m]: the
            chained scan matches' drift, well under the wheels' alone.
        heading_drift: the heading's grows by this much per radian turned [rad/rad].
        min_position_std: the reported position uncertainty at the anchor [m].
        min_heading_std: the same for heading [rad].
    """

    slam: SlamConfig = field(default_factory=lambda: SlamConfig(range_max=12.0,
                                                                loop_node_stride=5))
    use_imu: bool = True
    gyro_bias_time_constant: float = 60.0
    max_gyro_bias: float = 0.02
    drift: float = 0.01
    heading_drift: float = 0.01
    min_position_std: float = 0.01
    min_heading_std: float = math.radians(0.25)


class OdometryFrameLocalizer:
    """A :class:`~polynav.localization.interface.Localizer` for navigation without a map.

    ``set_map`` is accepted and ignored (the frame is the odometry frame, whatever map a caller
    holds); the state is UNINITIALIZED until the first scan, then TRACKING. ``quality`` is the
    share of recent scans the SLAM could match (a robot in an empty hall sees nothing to match).
    """

    def __init__(self, config: OdometryFrameConfig | None = None) -> None:
        self.config = config or OdometryFrameConfig()
        self._slam = Slam(self.config.slam)
        self._anchor = Pose2D()  # estimate frame <- fused odometry frame
        self._pending: Pose2D | None = None
        self._fused: Pose2D | None = None
        self._last_odometry: Pose2D | None = None
        self._last_imu_yaw: float | None = None
        self._last_imu_stamp: float | None = None
        self._bias_sum = 0.0
        self._bias_time = 0.0
        self._scan_fused: Pose2D | None = None  # fused odometry at the last matched scan
        self._scan_pose: Pose2D | None = None  # the SLAM's pose at that scan
        self._last_scan_stamp: float | None = None
        self._pose = Pose2D()
        self._stamp = 0.0
        self._quality = 0.0
        self._state = LocalizationState.UNINITIALIZED
        self._stamps: deque[float] = deque()
        self._history: deque[Pose2D] = deque()
        self.scans = 0
        self._covariance = PoseCovariance(min_position=self.config.min_position_std,
                                          min_heading=self.config.min_heading_std)

    # -- Localizer -----------------------------------------------------------------------------

    def set_map(self, grid: Map) -> None:
        """Ignored: navigation without a map localizes in the odometry frame."""

    def initialize(self, pose: Pose2D, now: float) -> None:
        """Make ``pose`` the current pose and restart the local map around it."""
        self._slam = Slam(self.config.slam)
        self._covariance.reset(0.0, 0.0)  # the floor: the frame is defined by this pose
        self._scan_fused = self._scan_pose = None
        if self._fused is None:
            self._pending = pose  # anchored on the first odometry reading
        else:
            self._anchor = pose.compose(self._fused.inverse())
        self._pose = pose
        self._stamp = now
        log.info("mapless localization anchored at %s", pose)

    def update(
        self,
        odometry: Odometry,
        imu: ImuReading | None,
        scan: LaserScan | None,
        now: float,
    ) -> LocalizationEstimate:
        """Predict with odometry and IMU, match ``scan`` when it is new, return the estimate."""
        self._predict(odometry, imu)
        self._stamp = now
        assert self._fused is not None
        if scan is not None and scan.stamp != self._last_scan_stamp:
            self._last_scan_stamp = scan.stamp
            self._match(scan)
        if self._scan_pose is not None and self._scan_fused is not None:
            self._pose = self._scan_pose.compose(self._fused.relative_to(self._scan_fused))
        else:
            self._pose = self._anchor.compose(self._fused)
        return self.estimate

    @property
    def estimate(self) -> LocalizationEstimate:
        return LocalizationEstimate(self._stamp, self._pose, float(self._quality), self._state,
                                    self._covariance.uncertainty)

    # -- internals -----------------------------------------------------------------------------

    def _predict(self, odometry: Odometry, imu: ImuReading | None) -> None:
        last = self._last_odometry
        self._last_odometry = odometry.pose
        if last is None:
            self._fused = odometry.pose
            if self._pending is not None:
                self._anchor = self._pending.compose(odometry.pose.inverse())
                self._pending = None
            self._remember(odometry.stamp)
            return
        delta = odometry.pose.relative_to(last)
        rotation = delta.theta
        if imu is not None and self.config.use_imu:
            if self._last_imu_yaw is not None and self._last_imu_stamp is not None:
                dt = max(0.0, imu.stamp - self._last_imu_stamp)
                turn = angle_diff(imu.yaw, self._last_imu_yaw)
                if abs(delta.x) + abs(delta.y) < 1e-9 and abs(delta.theta) < 1e-9:
                    rotation = 0.0  # the wheels stand: what the gyro turned is its bias
                    self._learn_bias(turn, dt)
                else:
                    bias = self._gyro_bias()
                    rotation = turn - bias * dt
                    self._learn_bias(bias * dt, dt)
            self._last_imu_yaw = imu.yaw
            self._last_imu_stamp = imu.stamp
        assert self._fused is not None
        self._fused = self._fused.compose(Pose2D(delta.x, delta.y, rotation))
        self._covariance.predict(math.hypot(delta.x, delta.y), rotation,
                                 drift=self.config.drift, heading_drift=self.config.heading_drift)
        self._remember(odometry.stamp)

    def _gyro_bias(self) -> float:
        bias = self._bias_sum / (self._bias_time + 5.0)  # a zero prior worth 5 s of evidence
        limit = self.config.max_gyro_bias
        return max(-limit, min(limit, bias))

    def _learn_bias(self, heading: float, dt: float) -> None:
        keep = math.exp(-dt / self.config.gyro_bias_time_constant)
        self._bias_sum = keep * self._bias_sum + heading
        self._bias_time = keep * self._bias_time + dt

    def _remember(self, stamp: float) -> None:
        assert self._fused is not None
        if self._stamps and stamp < self._stamps[-1]:
            self._stamps.clear()
            self._history.clear()
        if self._stamps and stamp == self._stamps[-1]:
            self._history[-1] = self._fused
        else:
            self._stamps.append(stamp)
            self._history.append(self._fused)
        while len(self._stamps) > 2 and self._stamps[0] < stamp - _HISTORY_SECONDS:
            self._stamps.popleft()
            self._history.popleft()

    def _fused_at(self, stamp: float) -> Pose2D:
        """The fused odometry at ``stamp``, interpolated (a scan is older than the tick)."""
        stamps, poses = self._stamps, self._history
        k = bisect.bisect_left(stamps, stamp)
        if k <= 0:
            return poses[0]
        if k >= len(stamps):
            return poses[-1]
        t0, t1 = stamps[k - 1], stamps[k]
        a, b = poses[k - 1], poses[k]
        f = (stamp - t0) / (t1 - t0) if t1 > t0 else 1.0
        return Pose2D(a.x + f * (b.x - a.x), a.y + f * (b.y - a.y),
                      a.theta + f * angle_diff(b.theta, a.theta))

    def _match(self, scan: LaserScan) -> None:
        at_scan = self._fused_at(scan.stamp)
        failed = self._slam.failed_matches
        pose = self._slam.add_scan(self._anchor.compose(at_scan), scan.ranges, scan.angles,
                                   scan.stamp, sensor_pose=scan.sensor_pose)
        matched = 0.0 if self._slam.failed_matches > failed else 1.0
        self._quality = matched if self.scans == 0 else 0.9 * self._quality + 0.1 * matched
        self.scans += 1
        self._scan_fused, self._scan_pose = at_scan, pose
        self._state = LocalizationState.TRACKING
