"""The pose tracker's settings (:class:`PoseTrackerConfig`), apart from the tracker itself.

Kept in a module of its own so the tracker's module holds behaviour only; the config is re-exported
from :mod:`~polynav.localization.pose_tracker`, where callers have always found it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from polynav.errors import ConfigError


@dataclass(frozen=True, slots=True)
class PoseTrackerConfig:
    """How the tracker predicts, matches and judges its pose.

    Attributes:
        sigma: standard deviation of the likelihood-field endpoint model [m].
        max_distance: cap of the distance field [m].
        beam_step: use every ``beam_step``-th beam while tracking.
        relocalize_beam_step: use every ``relocalize_beam_step``-th beam when relocalizing or
            lost (more beams make a wide search harder to fool).
        track_window_xy: half-width of the tracking search window in x and y [m].
        track_window_theta: half-width of the tracking heading window [rad].
        theta_step: fine heading step of every search [rad].
        coarse_cells: translation step of the coarse level of wide searches [cells].
        coarse_theta_step: heading step of the coarse level [rad].
        candidates: coarse poses refined by the fine level.
        prior_xy: standard deviation of the tracking prior around the prediction [m]; it only
            breaks ties along directions the scan does not constrain.
        prior_theta: the same for heading [rad].
        relocalize_window_xy: half-width of the relocalization window [m] after initialize.
        relocalize_window_theta: half-width of the relocalization heading window [rad].
        lost_window_xy: half-width of the search window while lost [m].
        lost_window_theta: half-width of the heading window while lost [rad].
        relocalize_quality: inlier fraction a wide search must reach to be believed.
        accept_quality: inlier fraction below which a tracking match is not applied (the
            prediction is kept).
        inlier_distance: an endpoint this close to a map surface is an inlier [m].
        quality_smoothing: weight of each new scan in the smoothed quality, in (0, 1].
        lost_quality: smoothed quality below which the tracker starts counting towards LOST.
        lost_after: how long [s] the quality must stay low before the state becomes LOST.
        wide_search_interval: while relocalizing or lost, run the wide search at most this
            often [s] (it costs a few milliseconds; scans in between are skipped).
        max_correction_xy: largest translation applied by one correction while tracking [m].
        max_correction_theta: largest rotation applied by one correction while tracking [rad].
        use_imu: take rotation from the IMU's integrated yaw when a reading is given.
        min_information: endpoints' worth of map surface a direction of the pose needs in the
            match's normal matrix before the scan corrects it (see
            :mod:`~polynav.localization.degeneracy`). Along a corridor, across an open hall,
            or along the one wall in sight the match has less, and the correction is projected
            onto the directions that have it: odometry and IMU carry the rest, instead of the
            near-random pick of the search sliding the pose along the corridor. A few endpoints
            are plenty when they are real (a lidar return is good to a centimetre or two), but
            one or two could be a person's legs.
        heading_length_scale: metres one radian of heading counts as when comparing heading
            with translation in the normal matrix [m]; about the distance to the walls that fix
            heading.
        constraint_distance: endpoints within this distance of a map surface at the matched
            pose enter the normal matrix [m]; farther ones (people, clutter) say nothing.
        min_evidence_points: a scan with fewer usable endpoints than this (an open hall with
            the walls out of range) neither moves the quality nor counts towards LOST: it
            cannot contradict the pose, so it cannot be evidence that the robot is lost. Nor
            does it correct the pose: two returns twelve metres away pin a rotation about
            them on paper, and a person's legs would pin it just as well.
        odometry_drift: how fast the pose may drift [m per m travelled] while some direction
            of it goes unconstrained (odometry scale error and heading drift). The tracking
            window widens by this much per metre travelled since the scan last fixed position
            in every direction, up to ``lost_window_xy``, so that after a long aisle or an open
            hall the match can still reach the walls that come into view; a widened window is
            searched coarse-to-fine.
        gyro_bias_time_constant: time constant [s] of the running estimate of the gyro's bias,
            learnt from the heading corrections the scan makes while it constrains heading and
            subtracted from the IMU's rotation, so that a stretch where the scan fixes no
            heading (an open hall) drifts as little as the gyro's noise, not its bias; 0 turns
            the estimate off.
        max_gyro_bias: the bias estimate is clamped to this [rad/s], so a run of wrong matches
            cannot teach the tracker a spin.
        standstill_interval: while the odometry has not moved since a match found the pose
            settled, match at most this often [s]; 0 matches every scan.
        settled_xy: a tracking correction smaller than this leaves the pose settled [m].
        settled_theta: the same for heading [rad].
        match_sigma: the error [m] one matched endpoint stands for when the match's information
            shrinks the reported uncertainty (:mod:`~polynav.localization.uncertainty`); more
            than the lidar's noise, as endpoints on one wall are not independent.
        heading_drift: the heading's uncertainty grows by this much per radian turned without
            a scan fixing it [rad/rad] (the position's by ``odometry_drift`` per metre).
        min_position_std: floor of the reported position uncertainty [m] (map cells and
            search steps the match's information does not see).
        min_heading_std: floor of the reported heading uncertainty [rad].
    """

    sigma: float = 0.05
    max_distance: float = 0.5
    beam_step: int = 4
    relocalize_beam_step: int = 2
    track_window_xy: float = 0.15
    track_window_theta: float = math.radians(6.0)
    theta_step: float = math.radians(0.5)
    coarse_cells: int = 2
    coarse_theta_step: float = math.radians(2.0)
    candidates: int = 8
    prior_xy: float = 0.5
    prior_theta: float = 0.5
    relocalize_window_xy: float = 1.0
    relocalize_window_theta: float = math.radians(30.0)
    lost_window_xy: float = 1.0
    lost_window_theta: float = math.radians(30.0)
    relocalize_quality: float = 0.6
    accept_quality: float = 0.3
    inlier_distance: float = 0.1
    quality_smoothing: float = 0.3
    lost_quality: float = 0.35
    lost_after: float = 3.0
    wide_search_interval: float = 0.5
    max_correction_xy: float = 0.04
    max_correction_theta: float = math.radians(2.0)
    use_imu: bool = True
    min_information: float = 4.0
    heading_length_scale: float = 1.0
    constraint_distance: float = 0.15
    min_evidence_points: int = 10
    odometry_drift: float = 0.02
    gyro_bias_time_constant: float = 120.0
    max_gyro_bias: float = 0.02
    standstill_interval: float = 1.0
    settled_xy: float = 0.01
    settled_theta: float = math.radians(0.3)
    match_sigma: float = 0.05
    heading_drift: float = 0.02
    min_position_std: float = 0.01
    min_heading_std: float = math.radians(0.25)

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if isinstance(value, float) and not math.isfinite(value):
                _fail(f.name, f"must be finite, got {value}")
        positive = (
            "sigma", "max_distance", "track_window_theta", "theta_step", "coarse_theta_step",
            "prior_xy", "prior_theta", "relocalize_window_xy", "relocalize_window_theta",
            "lost_window_xy", "lost_window_theta", "inlier_distance", "quality_smoothing",
            "max_correction_xy", "max_correction_theta", "heading_length_scale",
            "constraint_distance", "settled_xy", "settled_theta", "match_sigma",
            "min_position_std", "min_heading_std",
        )
        for name in positive:
            if not getattr(self, name) > 0.0:
                _fail(name, f"must be > 0, got {getattr(self, name)}")
        for name in ("track_window_xy", "lost_after", "wide_search_interval", "min_information",
                     "odometry_drift",
                     "gyro_bias_time_constant", "max_gyro_bias", "min_evidence_points",
                     "standstill_interval", "heading_drift"):
            if not getattr(self, name) >= 0.0:
                _fail(name, f"must be >= 0, got {getattr(self, name)}")
        for name in ("beam_step", "relocalize_beam_step", "coarse_cells", "candidates"):
            if not getattr(self, name) >= 1:
                _fail(name, f"must be >= 1, got {getattr(self, name)}")
        for name in ("relocalize_quality", "accept_quality", "lost_quality"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                _fail(name, f"must be in [0, 1], got {getattr(self, name)}")
        if self.quality_smoothing > 1.0:
            _fail("quality_smoothing", f"must be <= 1, got {self.quality_smoothing}")
        for name in ("track_window_theta", "relocalize_window_theta", "lost_window_theta"):
            if getattr(self, name) >= math.pi:
                _fail(name, f"must be < pi, got {getattr(self, name)}")
        if self.coarse_theta_step < self.theta_step:
            _fail("coarse_theta_step", "must be >= theta_step")


def _fail(name: str, reason: str) -> None:
    raise ConfigError(f"localization.{name}", reason)
