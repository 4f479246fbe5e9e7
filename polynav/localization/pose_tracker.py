"""The pose tracker: odometry and IMU prediction corrected by matching each scan to the map.

:class:`PoseTracker` implements :class:`~polynav.localization.interface.Localizer`.

**Prediction.** Each :meth:`PoseTracker.update` moves the map pose by the odometry increment
(the new odometry pose expressed in the previous one's frame); when an IMU reading is given, its
integrated-yaw increment replaces the wheels' rotation, which slip and scale more than a gyro.
The gyro's bias is learnt on the way (the heading corrections the scan makes, over time) and
subtracted, so that where no wall fixes heading the pose drifts by the gyro's noise only.

**Correction.** Each *new* scan (by stamp) is matched with the correlative matcher
(:mod:`~polynav.localization.scan_matcher`) in a narrow window around the pose predicted *at the
scan's stamp*: the tracker keeps a second of odometry history, so a scan read a few tens of
milliseconds after it was taken is not matched as if it had been taken now (at 1 m/s, 50 ms is
5 cm). The correction found at the scan's stamp is carried forward through the odometry since.
While tracking, each correction is clamped to ``max_correction_xy`` / ``max_correction_theta``,
so a controller at 20 Hz never sees a jump of more than a few centimetres; a larger error is
worked off over the next scans.

**Degenerate geometry.** A corridor pins the pose across it and in heading, never along it; an
open hall with the walls out of range pins nothing. Each tracking correction is therefore
projected onto the directions the match constrains, read from the eigen-decomposition of its
Gauss-Newton normal matrix (:mod:`~polynav.localization.degeneracy`, ``min_information``):
along the others odometry and IMU carry the pose, instead of the search's near-arbitrary pick
there. While some direction goes unconstrained the tracking window widens with the distance
travelled (``odometry_drift``), so the walls that come into view at the end of the aisle or
hall are within its reach.

**Standing still.** While tracking, once a match has found the pose settled (a correction under
a centimetre and a few tenths of a degree), scans taken before the wheels next move are matched
at most every ``standstill_interval`` seconds: the same scan of the same walls would only find
the same pose again. A robot waiting for a lift, a person or another robot then costs little,
and a fleet of them too; people walking past do not move a standing pose, and the periodic match
still catches a robot carried away on the spot.

**Quality** is the fraction of used endpoints within ``inlier_distance`` of a map surface at the
matched pose, smoothed by an exponential moving average over scans. It is 1 when the scan fits
the map (in a corridor too: the walls fit, whatever the match cannot tell along it), and falls
with people, moved furniture, or a wrong pose or map. A scan with fewer than
``min_evidence_points`` endpoints (nothing in range) leaves it, and the LOST timer, as they
were: it contradicts nothing.

**States.**

- ``UNINITIALIZED`` before :meth:`PoseTracker.initialize`, and after it until a wide
  relocalization search (``relocalize_window_xy`` / ``relocalize_window_theta`` around the given
  pose, carried along by odometry) finds a match with at least ``relocalize_quality`` inliers.
  Until then the reported pose is the given one moved by odometry, with quality 0. We chose
  UNINITIALIZED over "TRACKING with low quality" so that nobody drives on a pose that the scan
  has not confirmed.
- ``TRACKING`` once relocalized. When the smoothed quality stays below ``lost_quality`` for
  ``lost_after`` seconds of ``now`` (never the wall clock), the state becomes ``LOST``. A
  relocalization that has not succeeded ``lost_after`` seconds after :meth:`initialize` also
  ends in ``LOST``.
- ``LOST`` keeps predicting and searches the wider ``lost_window_xy`` / ``lost_window_theta``
  around the prediction, at most every ``wide_search_interval`` seconds (a wide search costs a
  few milliseconds, a tracking correction a fraction of one); a match with at least
  ``relocalize_quality`` inliers is taken (unclamped: the pose is known to be wrong) and the
  state returns to ``TRACKING``.
"""

from __future__ import annotations

import bisect
import logging
import math
from collections import deque

import numpy as np
import numpy.typing as npt

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D, angle_diff, wrap_angle
from polynav.localization import degeneracy, scan_matcher
from polynav.localization.degeneracy import Constraint
from polynav.localization.interface import LocalizationEstimate, LocalizationState
from polynav.localization.likelihood_field import build_likelihood_field
from polynav.localization.pose_tracker_config import PoseTrackerConfig
from polynav.localization.scan_matcher import Match, ScanMatcher, SearchWindow
from polynav.localization.uncertainty import PoseCovariance
from polynav.maps.map import Map
from polynav.robot.interface import ImuReading, LaserScan, Odometry

log = logging.getLogger(__name__)

_HISTORY_SECONDS = 1.0
_BIAS_PRIOR_SECONDS = 2.0

__all__ = ["PoseTracker", "PoseTrackerConfig", "warm_up"]


class PoseTracker:
    """Scan-to-map pose tracking on noisy odometry, IMU and lidar (see the module docstring).

    Args:
        config: the tracker's settings.

    Attributes:
        last_match: the newest scan match, for diagnostics (pose, score, inlier fraction).
        last_constraint: the directions the newest tracking match constrained, for
            diagnostics (``None`` before the first).
    """

    def __init__(self, config: PoseTrackerConfig = PoseTrackerConfig()) -> None:  # noqa: B008
        self.config = config
        self._matcher: ScanMatcher | None = None
        self._pose = Pose2D()
        self._state = LocalizationState.UNINITIALIZED
        self._quality = 0.0
        self._stamp = 0.0
        self._awaiting_relocalization = False
        self._initialized_at = 0.0
        self._low_since: float | None = None
        self._next_wide_search = -math.inf
        self._last_odometry: Pose2D | None = None
        self._last_imu_yaw: float | None = None
        self._last_imu_stamp: float | None = None
        # Running gyro-bias estimate: bias = _bias_sum / (_bias_time + prior time).
        self._bias_sum = 0.0
        self._bias_time = 0.0
        self._unfixed_travel = 0.0  # [m] since the scan last fixed x and y both
        self._last_scan_stamp: float | None = None
        # Odometry pose and time of the last match that found the pose settled while tracking.
        self._settled_at: tuple[Pose2D, float] | None = None
        self._history_stamps: deque[float] = deque()
        self._history_poses: deque[Pose2D] = deque()
        self._beam_cache: tuple[tuple[float, float, int], npt.NDArray[np.float64]] | None = None
        self.last_match: Match | None = None
        self.last_constraint: Constraint | None = None
        self._covariance = PoseCovariance(min_position=config.min_position_std,
                                          min_heading=config.min_heading_std)

    # -- Localizer -----------------------------------------------------------------------------

    def set_map(self, grid: Map) -> None:
        """Localize against ``grid`` from now on; the state becomes UNINITIALIZED.

        Builds the likelihood field (tens of milliseconds on a building floor).
        """
        c = self.config
        field = build_likelihood_field(grid, sigma=c.sigma, max_distance=c.max_distance)
        self._matcher = ScanMatcher(field, coarse_cells=c.coarse_cells)
        self._set_state(LocalizationState.UNINITIALIZED, self._stamp)
        self._awaiting_relocalization = False
        self._quality = 0.0
        self._low_since = None

    def initialize(self, pose: Pose2D, now: float) -> None:
        """Start (or restart) tracking near ``pose``; the next scans relocalize within the
        relocalization window, and only then does the state become TRACKING.

        Raises:
            InvalidRequest: no map has been set.
        """
        if self._matcher is None:
            raise InvalidRequest("map", "no map to localize on: set_map first")
        self._pose = pose
        self._stamp = now
        self._quality = 0.0
        self._low_since = None
        self._awaiting_relocalization = True
        self._unfixed_travel = 0.0
        self._initialized_at = now
        self._next_wide_search = -math.inf
        # The given pose is good to about the relocalization window, not better.
        self._covariance.reset(self.config.relocalize_window_xy,
                               self.config.relocalize_window_theta)
        self._set_state(LocalizationState.UNINITIALIZED, now)
        log.info("localization initialized near %s", pose)

    def update(
        self,
        odometry: Odometry,
        imu: ImuReading | None,
        scan: LaserScan | None,
        now: float,
    ) -> LocalizationEstimate:
        """Predict with odometry/IMU, correct with ``scan`` when it is new, return the estimate.

        Args:
            odometry: the newest wheel odometry.
            imu: the newest IMU reading, if any.
            scan: the newest scan, if any; one already used (same stamp) is ignored.
            now: current time [s] (the robot's clock), used for the LOST timer.
        """
        self._predict(odometry, imu)
        self._stamp = now
        active = self._awaiting_relocalization or (
            self._state is not LocalizationState.UNINITIALIZED
        )
        if (
            scan is not None
            and self._matcher is not None
            and active
            and scan.stamp != self._last_scan_stamp
        ):
            self._last_scan_stamp = scan.stamp
            self._correct(scan, odometry.pose, now)
        self._check_lost(now)
        return self.estimate

    @property
    def estimate(self) -> LocalizationEstimate:
        """The newest estimate (quality 0 while UNINITIALIZED)."""
        quality = 0.0 if self._state is LocalizationState.UNINITIALIZED else self._quality
        return LocalizationEstimate(self._stamp, self._pose, float(quality), self._state,
                                    self._covariance.uncertainty)

    @property
    def _imu_used(self) -> bool:
        return self.config.use_imu and self._last_imu_stamp is not None

    # -- prediction ----------------------------------------------------------------------------

    def _predict(self, odometry: Odometry, imu: ImuReading | None) -> None:
        last = self._last_odometry
        delta = Pose2D() if last is None else odometry.pose.relative_to(last)
        rotation = delta.theta
        if imu is not None and self.config.use_imu:
            if (self._last_imu_yaw is not None and self._last_imu_stamp is not None
                    and last is not None):
                dt = max(0.0, imu.stamp - self._last_imu_stamp)
                turn = angle_diff(imu.yaw, self._last_imu_yaw)
                standing = (abs(delta.x) + abs(delta.y) < 1e-9 and abs(delta.theta) < 1e-9)
                if standing:
                    # The wheels do not turn: whatever the gyro integrated is its bias (a
                    # zero-velocity update), and the robot did not turn. Learnt before the
                    # robot first drives, it keeps dead reckoning straight across an open
                    # hall where no scan corrects the heading.
                    rotation = 0.0
                    self._learn_bias(turn, dt)
                else:
                    bias = self.gyro_bias
                    rotation = turn - bias * dt
                    self._learn_bias(bias * dt, dt)
            self._last_imu_yaw = imu.yaw
            self._last_imu_stamp = imu.stamp
        self._last_odometry = odometry.pose
        if last is not None:
            self._pose = self._pose.compose(Pose2D(delta.x, delta.y, rotation))
            self._unfixed_travel += math.hypot(delta.x, delta.y)
            self._covariance.predict(math.hypot(delta.x, delta.y), rotation,
                                     drift=self.config.odometry_drift,
                                     heading_drift=self.config.heading_drift)
        self._remember(odometry.stamp, odometry.pose)

    def _remember(self, stamp: float, odom: Pose2D) -> None:
        stamps, poses = self._history_stamps, self._history_poses
        if stamps and stamp < stamps[-1]:
            stamps.clear()
            poses.clear()
        if stamps and stamp == stamps[-1]:
            poses[-1] = odom
        else:
            stamps.append(stamp)
            poses.append(odom)
        while len(stamps) > 2 and stamps[0] < stamp - _HISTORY_SECONDS:
            stamps.popleft()
            poses.popleft()

    def _odometry_at(self, stamp: float) -> Pose2D:
        """Odometry pose at ``stamp``, interpolated in the history (clamped to its ends)."""
        stamps, poses = self._history_stamps, self._history_poses
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

    @property
    def gyro_bias(self) -> float:
        """The gyro bias [rad/s] the tracker currently subtracts from the IMU's rotation."""
        c = self.config
        if c.gyro_bias_time_constant <= 0.0:
            return 0.0
        # A prior of zero bias weighs as much as a few seconds of evidence.
        bias = self._bias_sum / (self._bias_time + _BIAS_PRIOR_SECONDS)
        return max(-c.max_gyro_bias, min(c.max_gyro_bias, bias))

    def _learn_bias(self, heading: float, dt: float) -> None:
        """Add ``heading`` [rad] of bias evidence over ``dt`` [s], forgetting old evidence.

        The bias subtracted during a prediction goes in as evidence for itself, and each heading
        correction the scan makes goes in with the opposite sign (a gyro reading high makes the
        pose turn too far, which the scan turns back): the sum over time is the raw bias times
        the time, whatever estimate was used on the way.
        """
        tau = self.config.gyro_bias_time_constant
        if tau <= 0.0:
            return
        keep = math.exp(-dt / tau)
        self._bias_sum = keep * self._bias_sum + heading
        self._bias_time = keep * self._bias_time + dt

    # -- correction ----------------------------------------------------------------------------

    def _correct(self, scan: LaserScan, odom_now: Pose2D, now: float) -> None:
        assert self._matcher is not None
        c = self.config
        # Motion since the scan was taken, in the robot frame at the scan's stamp.
        since_scan = odom_now.relative_to(self._odometry_at(scan.stamp))
        at_scan = self._pose.compose(since_scan.inverse())
        tracking = self._state is LocalizationState.TRACKING
        if not tracking and now < self._next_wide_search:
            return
        if tracking and self._standing_settled(scan.stamp, now):
            return
        step = c.beam_step if tracking else c.relocalize_beam_step
        points = scan_matcher.scan_points(
            scan.ranges, self._beam_angles(scan), range_min=scan.range_min,
            range_max=scan.range_max, sensor_pose=scan.sensor_pose, step=step,
        )
        if tracking:
            xy = min(max(c.lost_window_xy, c.track_window_xy),
                     c.track_window_xy + c.odometry_drift * self._unfixed_travel)
            window = SearchWindow(xy, c.track_window_theta, c.theta_step,
                                  coarse=xy > 1.5 * c.track_window_xy,
                                  coarse_theta_step=c.coarse_theta_step,
                                  candidates=c.candidates)
            match = self._matcher.match(points, at_scan, window, prior_xy=c.prior_xy,
                                        prior_theta=c.prior_theta,
                                        inlier_distance=c.inlier_distance)
        else:
            if self._awaiting_relocalization and points.shape[0] < c.min_evidence_points:
                # Started where the lidar sees nothing (an open hall): not a failed
                # relocalization yet; odometry carries the given pose until walls come in view.
                self._initialized_at = now
                return
            wide_xy, wide_theta = (
                (c.relocalize_window_xy, c.relocalize_window_theta)
                if self._awaiting_relocalization
                else (c.lost_window_xy, c.lost_window_theta)
            )
            # As far as odometry may have drifted since the pose was last fixed, not less.
            wide_xy = max(wide_xy, min(4.0 * wide_xy, c.odometry_drift * self._unfixed_travel))
            window = SearchWindow(wide_xy, wide_theta, c.theta_step, coarse=True,
                                  coarse_theta_step=c.coarse_theta_step,
                                  candidates=c.candidates)
            match = self._matcher.match(points, at_scan, window, prior_xy=4.0 * wide_xy,
                                        prior_theta=4.0 * wide_theta,
                                        inlier_distance=c.inlier_distance)
            self._next_wide_search = now + c.wide_search_interval
        self.last_match = match
        quality = match.inliers if match.points else 0.0

        if tracking:
            self._settled_at = None
            evidence = match.points >= c.min_evidence_points
            if evidence and quality >= c.accept_quality:
                information = self._matcher.information(
                    points, match.pose, max_distance=c.constraint_distance)
                con = degeneracy.constraint(information, length_scale=c.heading_length_scale,
                                            min_information=c.min_information)
                self.last_constraint = con
                target = con.project(at_scan, match.pose)
                corrected = _clamp_step(at_scan, target, c.max_correction_xy,
                                        c.max_correction_theta)
                self._covariance.correct(con, match_sigma=c.match_sigma)
                self._covariance.add_offset(target.x - corrected.x, target.y - corrected.y,
                                            angle_diff(target.theta, corrected.theta))
                settled = (math.hypot(target.x - at_scan.x, target.y - at_scan.y) < c.settled_xy
                           and abs(angle_diff(target.theta, at_scan.theta)) < c.settled_theta)
                self._settled_at = (self._odometry_at(scan.stamp), now) if settled else None
                if not any(abs(v[0]) + abs(v[1]) > 0.1 for v in con.unconstrained_directions()):
                    # Position is fixed in every direction, up to what the clamp left for the
                    # next scans: the window keeps room for that much.
                    left = math.hypot(target.x - corrected.x, target.y - corrected.y)
                    self._unfixed_travel = (left / c.odometry_drift if c.odometry_drift > 0.0
                                            else 0.0)
                self._pose = corrected.compose(since_scan)
                if self._imu_used:
                    self._learn_bias(-angle_diff(corrected.theta, at_scan.theta), 0.0)
            if evidence:
                self._smooth_quality(quality)
                if self._quality >= c.lost_quality:
                    self._low_since = None
                elif self._low_since is None:
                    self._low_since = now
        elif quality >= c.relocalize_quality:
            self._pose = match.pose.compose(since_scan)
            information = self._matcher.information(points, match.pose,
                                                    max_distance=c.constraint_distance)
            self._covariance.reset(wide_xy, wide_theta)
            self._covariance.correct(
                degeneracy.constraint(information, length_scale=c.heading_length_scale,
                                      min_information=c.min_information),
                match_sigma=c.match_sigma)
            self._unfixed_travel = 0.0
            self._quality = quality
            self._low_since = None
            self._awaiting_relocalization = False
            log.info("localization relocalized at %s (quality %.2f)", match.pose, quality)
            self._set_state(LocalizationState.TRACKING, now)
        else:
            self._smooth_quality(quality)

    def _standing_settled(self, stamp: float, now: float) -> bool:
        """The wheels have not moved since a match found the pose settled, not long ago."""
        if self._settled_at is None:
            return False
        odometry, at = self._settled_at
        if now - at >= self.config.standstill_interval:
            return False
        moved = self._odometry_at(stamp).relative_to(odometry)
        return abs(moved.x) + abs(moved.y) < 1e-6 and abs(moved.theta) < 1e-6

    def _check_lost(self, now: float) -> None:
        """The LOST timers, checked at every update so they fire on time between scans."""
        c = self.config
        if self._state is LocalizationState.TRACKING:
            if self._low_since is not None and now - self._low_since >= c.lost_after:
                log.warning("localization lost: quality %.2f below %.2f for %.1f s",
                            self._quality, c.lost_quality, now - self._low_since)
                self._set_state(LocalizationState.LOST, now)
                self._next_wide_search = now
        elif (self._awaiting_relocalization
              and now - self._initialized_at >= c.lost_after):
            log.warning("relocalization failed for %.1f s near %s", now - self._initialized_at,
                        self._pose)
            self._awaiting_relocalization = False
            self._set_state(LocalizationState.LOST, now)

    def _smooth_quality(self, quality: float) -> None:
        a = self.config.quality_smoothing
        self._quality = (1.0 - a) * self._quality + a * quality

    def _beam_angles(self, scan: LaserScan) -> npt.NDArray[np.float64]:
        key = (scan.angle_min, scan.angle_increment, int(scan.ranges.shape[0]))
        if self._beam_cache is None or self._beam_cache[0] != key:
            self._beam_cache = (key, scan.angles)
        return self._beam_cache[1]

    def _set_state(self, state: LocalizationState, now: float) -> None:
        self._settled_at = None
        if state is not self._state:
            log.info("localization %s -> %s at t=%.3f", self._state.value, state.value, now)
            self._state = state


def _clamp_step(start: Pose2D, target: Pose2D, max_xy: float, max_theta: float) -> Pose2D:
    """``target``, or the pose ``max_xy`` / ``max_theta`` from ``start`` towards it."""
    dx, dy = target.x - start.x, target.y - start.y
    dist = math.hypot(dx, dy)
    f = 1.0 if dist <= max_xy else max_xy / dist
    dtheta = angle_diff(target.theta, start.theta)
    dtheta = max(-max_theta, min(max_theta, dtheta))
    return Pose2D(start.x + f * dx, start.y + f * dy, wrap_angle(start.theta + dtheta))


def warm_up() -> None:
    """Compile the numba kernels (see :func:`polynav.localization.scan_matcher.warm_up`)."""
    scan_matcher.warm_up()
