"""Global relocalization: where on a saved map is the robot, with no prior at all?

The same exact branch-and-bound search that closes SLAM loops (:mod:`polynav.mapping.
branch_and_bound`), run over the whole floor and every heading: the map is cut into square tiles
and each tile is searched in four quarter-turns of heading, so that the best pose of every
place-and-heading is known, not only the best one overall. A robot is found when the best pose
scores above ``min_score`` *and* beats every distinct alternative (farther than ``distinct_xy``
or ``distinct_theta`` from it) by ``margin``: in a featureless hall or between two identical
rooms several poses explain the scan equally well, and the answer is then "ambiguous", never a
confident wrong pose. The winner is refined by the correlative scan matcher.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.errors import ConfigError
from polynav.geometry import Pose2D, angle_diff
from polynav.localization.likelihood_field import build_likelihood_field
from polynav.localization.scan_matcher import ScanMatcher, SearchWindow, scan_points
from polynav.mapping import branch_and_bound
from polynav.maps.map import Map
from polynav.robot.interface import LaserScan

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class RelocalizationConfig:
    """The global search [m, rad].

    Attributes:
        sigma: width of the endpoint model; wider than tracking's, so that a pose a few
            centimetres off still scores (the search steps a whole cell and half a degree).
        depth: branch-and-bound levels (the coarsest block is ``2^depth`` cells).
        tile: side of the square tiles the floor is searched in.
        theta_step: heading step of the search.
        points: scan endpoints used (spread evenly over the scan).
        range_max: returns beyond this are not used (sparse, and long lever arms).
        min_score: a pose scoring below this (mean likelihood of the endpoints, 0..1) is no
            match.
        margin: the winner must beat every distinct alternative by this much.
        distinct_xy, distinct_theta: an alternative this far from the winner is distinct.
    """

    sigma: float = 0.1
    depth: int = 6
    tile: float = 4.0
    theta_step: float = math.radians(0.75)
    points: int = 120
    range_max: float = 12.0
    min_score: float = 0.5
    margin: float = 0.08
    distinct_xy: float = 1.0
    distinct_theta: float = 0.5

    def __post_init__(self) -> None:
        for key in ("sigma", "tile", "theta_step", "range_max", "distinct_xy", "distinct_theta"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value > 0.0):
                raise ConfigError(f"mapping.relocalization.{key}", f"must be > 0, got {value}")
        if not 1 <= self.depth <= 10:
            raise ConfigError("mapping.relocalization.depth", "must be within 1..10")
        if self.points < 10:
            raise ConfigError("mapping.relocalization.points", "must be >= 10")
        if not 0.0 < self.min_score < 1.0 or not 0.0 <= self.margin < 1.0:
            raise ConfigError("mapping.relocalization.min_score", "scores are within (0, 1)")


@dataclass(frozen=True, slots=True)
class Relocalization:
    """The answer of one search.

    Attributes:
        pose: where the robot is, or ``None`` when it could not be told.
        score: the best pose's score (0..1).
        runner_up: the best distinct alternative's score (0 when none scored).
        reason: ``""`` when found; ``"no match"`` (nothing scores ``min_score``) or
            ``"ambiguous"`` (an alternative scores within ``margin``).
    """

    pose: Pose2D | None
    score: float
    runner_up: float
    reason: str = ""

    @property
    def found(self) -> bool:
        return self.pose is not None


class Relocalizer:
    """Finds scans on one map; build it once per map (the precomputation is the costly part)."""

    def __init__(self, grid: Map, config: RelocalizationConfig | None = None) -> None:
        self.config = cfg = config or RelocalizationConfig()
        info = grid.info
        if abs(info.origin.theta) > 1e-9:
            raise ConfigError("map.origin.theta", "relocalization needs an unrotated map origin")
        self._info = info
        field = build_likelihood_field(grid, sigma=cfg.sigma, max_distance=4.0 * cfg.sigma)
        self._pre = branch_and_bound.precompute(field.likelihood, cfg.depth)
        self._matcher = ScanMatcher(build_likelihood_field(grid))
        self._polish = SearchWindow(xy=0.1, theta=math.radians(2.0),
                                    theta_step=math.radians(0.25))
        free = grid.data == 0
        tile = max(1, int(round(cfg.tile / info.resolution)))
        self._tiles = [
            (ix + tile // 2, iy + tile // 2, tile // 2 + 1)
            for iy in range(0, info.height, tile)
            for ix in range(0, info.width, tile)
            if free[iy:iy + tile, ix:ix + tile].any()
        ]

    def locate(self, scan: LaserScan) -> Relocalization:
        """The robot's pose on the map from ``scan`` alone."""
        cfg, res = self.config, self._info.resolution
        points = self._points(scan)
        if points.shape[0] < 10:
            return Relocalization(None, 0.0, 0.0, "no match")
        quarter = 0.25 * math.pi
        candidates: list[tuple[float, Pose2D]] = []
        for cx, cy, half in self._tiles:
            for heading in (quarter, 3.0 * quarter, 5.0 * quarter, 7.0 * quarter):
                found = branch_and_bound.search(
                    self._pre, points / res, x=cx, y=cy, theta=heading, window_cells=half,
                    window_theta=quarter, theta_step=cfg.theta_step,
                    min_score=0.5 * cfg.min_score,
                )
                if found is not None:
                    origin = self._info.origin
                    pose = Pose2D(origin.x + found.x * res, origin.y + found.y * res,
                                  math.atan2(math.sin(found.theta), math.cos(found.theta)))
                    candidates.append((found.score, pose))
        if not candidates:
            return Relocalization(None, 0.0, 0.0, "no match")
        candidates.sort(key=lambda c: -c[0])
        best_score, best = candidates[0]
        runner_up = max(
            (score for score, pose in candidates[1:]
             if pose.distance_to(best) > cfg.distinct_xy
             or abs(angle_diff(pose.theta, best.theta)) > cfg.distinct_theta),
            default=0.0,
        )
        if best_score < cfg.min_score:
            return Relocalization(None, best_score, runner_up, "no match")
        if best_score - runner_up < cfg.margin:
            log.info("relocalization ambiguous: %.3f against %.3f", best_score, runner_up)
            return Relocalization(None, best_score, runner_up, "ambiguous")
        refined = self._matcher.match(points, best, self._polish).pose
        log.info("relocalized at %s (score %.3f, runner-up %.3f)", refined, best_score, runner_up)
        return Relocalization(refined, best_score, runner_up)

    def _points(self, scan: LaserScan) -> npt.NDArray[np.float64]:
        cfg = self.config
        points = scan_points(scan.ranges, scan.angles, range_min=0.05,
                             range_max=min(cfg.range_max, scan.range_max - 1e-6),
                             sensor_pose=scan.sensor_pose)
        if points.shape[0] > cfg.points:
            keep = np.linspace(0, points.shape[0] - 1, cfg.points).round().astype(np.int64)
            points = points[keep]
        return np.ascontiguousarray(points)
