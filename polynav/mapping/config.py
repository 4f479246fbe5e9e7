"""All SLAM parameters: one flat, frozen dataclass in SI units (STYLE R10).

The defaults are meant to work unchanged on the simulator's 360° lidar and on the Freiburg and
Mines logs (SICK 180°, Hokuyo 240°): nothing here is tuned per log.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from polynav.errors import ConfigError


@dataclass(frozen=True, slots=True)
class SlamConfig:
    """How the SLAM builds submaps, matches scans, closes loops and optimises the pose graph.

    Attributes:
        resolution: cell size of the submaps and of the final map [m].
        range_min: shorter returns are ignored [m] (the robot's own body).
        range_max: longer returns are ignored [m]; far returns are sparse and sensitive to
            heading error, and the logs' building is smaller than this.
        match_points: at most this many endpoints are used for matching (evenly subsampled
            beams); all valid endpoints are inserted into the submaps.
        node_min_translation: a scan becomes a pose-graph node once the robot has moved this far
            [m] since the last node (Cartographer's motion filter) ...
        node_min_rotation: ... or turned this much [rad]; other scans only get a pose.
        scans_per_submap: a new submap starts after this many nodes; each submap receives twice
            as many, so consecutive submaps overlap by half (Cartographer) and the one matched
            against always holds at least this many scans.
        hit_probability: occupancy probability a return raises its cell to, from 0.5.
        miss_probability: occupancy probability a beam passing through lowers a cell to.
        occupied_probability: a cell at or above this is an obstacle for matching and the map.
        free_probability: a cell at or below this is free in the final map.
        likelihood_sigma: standard deviation of the endpoint likelihood model [m].
        match_window_xy: half-width of the scan-to-submap translation search [m].
        match_window_theta: half-width of its heading search [rad].
        match_theta_step: its fine heading step [rad].
        match_prior_xy: standard deviation of the Gaussian prior around the odometry prediction
            that weighs the match score [m]: it keeps a featureless direction (along a
            corridor) where odometry put it instead of letting it slide to any equal fit.
        match_prior_theta: the same on heading [rad].
        match_min_score: a match scoring below this (mean endpoint likelihood) is not trusted:
            the node keeps its odometry prediction.
        loop_window_xy: half-width of the loop-closure translation search at most [m] ...
        loop_window_min_xy: ... and at least [m]; in between it grows by
            ``loop_window_growth`` per metre travelled since the last loop closure: the drift
            the search must cover is what built up since the trajectory was last tied down,
            and a window wider than that only finds the next room of a row of identical ones.
        loop_window_growth: that growth [m of window per m travelled].
        loop_window_theta: half-width of its heading search [rad].
        loop_theta_step: its heading step [rad].
        loop_depth: levels of the branch-and-bound precomputation; the coarsest level moves
            ``2**loop_depth`` cells at a time.
        loop_min_score: a loop closure is accepted at this mean endpoint likelihood or above.
        loop_max_distance: only finished submaps whose anchor is this close to the node's
            estimate are searched [m].
        loop_max_per_node: stop searching from a node after this many loop closures (the
            nearest submaps first).
        loop_node_stride: search for loop closures from every this-many-th node.
        optimize_every: optimise the pose graph after this many new nodes when a loop closure
            was added since the last optimisation.
        odom_sigma_xy: standard deviation of an odometry edge per metre travelled, plus a floor
            of one cell [m].
        odom_sigma_theta: standard deviation of an odometry edge's heading [rad].
        match_sigma_xy: standard deviation of a node-to-submap edge [m].
        match_sigma_theta: standard deviation of its heading [rad].
        loop_sigma_xy: standard deviation of a loop-closure edge [m].
        loop_sigma_theta: standard deviation of its heading [rad].
        huber_scale: the Huber loss turns linear beyond this many standard deviations, so a
            false loop closure pulls with a bounded force.
    """

    resolution: float = 0.05
    range_min: float = 0.1
    range_max: float = 25.0
    match_points: int = 200
    node_min_translation: float = 0.1
    node_min_rotation: float = math.radians(5.0)
    scans_per_submap: int = 10
    hit_probability: float = 0.7
    miss_probability: float = 0.4
    occupied_probability: float = 0.6
    free_probability: float = 0.45
    likelihood_sigma: float = 0.05
    match_window_xy: float = 0.5
    match_window_theta: float = math.radians(20.0)
    match_theta_step: float = math.radians(0.5)
    match_prior_xy: float = 0.25
    match_prior_theta: float = 0.35
    match_min_score: float = 0.1
    loop_window_xy: float = 4.0
    loop_window_min_xy: float = 1.0
    loop_window_growth: float = 0.1
    loop_window_theta: float = math.radians(30.0)
    loop_theta_step: float = math.radians(0.5)
    loop_depth: int = 6
    loop_min_score: float = 0.6
    loop_max_distance: float = 15.0
    loop_max_per_node: int = 2
    loop_node_stride: int = 2
    optimize_every: int = 20
    odom_sigma_xy: float = 0.1
    odom_sigma_theta: float = 0.05
    match_sigma_xy: float = 0.02
    match_sigma_theta: float = 0.005
    loop_sigma_xy: float = 0.05
    loop_sigma_theta: float = 0.01
    huber_scale: float = 2.0

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not math.isfinite(value) or value <= 0:
                raise ConfigError(f"mapping.slam.{f.name}", f"must be > 0, got {value}")
        if self.range_min >= self.range_max:
            raise ConfigError("mapping.slam.range_min", "must be below range_max")
        for name in ("hit_probability", "miss_probability", "occupied_probability",
                     "free_probability"):
            if not getattr(self, name) < 1.0:
                raise ConfigError(f"mapping.slam.{name}", "must be a probability below 1")
        if not self.miss_probability < 0.5 < self.hit_probability:
            raise ConfigError("mapping.slam.hit_probability",
                              "need miss_probability < 0.5 < hit_probability")
        if not self.free_probability < self.occupied_probability:
            raise ConfigError("mapping.slam.free_probability", "must be below occupied_probability")
        if self.loop_window_min_xy > self.loop_window_xy:
            raise ConfigError("mapping.slam.loop_window_min_xy", "must be at most loop_window_xy")
        if not 1 <= self.loop_depth <= 10:
            raise ConfigError("mapping.slam.loop_depth", "must be in 1..10")
        if not self.loop_min_score < 1.0 and self.match_min_score < 1.0:
            raise ConfigError("mapping.slam.loop_min_score", "scores are below 1")
