"""Global relocalization: where on a saved map is the robot, with no prior at all?

The same exact branch-and-bound search that closes SLAM loops (:mod:`polynav.mapping.
branch_and_bound`), run over the whole floor's free space and the whole circle of headings, twice:
once for the best pose, and once more with the winner's neighbourhood left out (poses within
``distinct_xy`` *and* ``distinct_theta`` of it), which gives the exact best *distinct*
alternative. A robot is found when the best pose scores at least ``min_score`` *and* beats that
alternative by ``margin``: in a featureless hall, along a corridor or between two identical rooms
several poses explain the scan equally well, and the answer is then "ambiguous", never a
confident wrong pose. The second search only looks for alternatives within two margins of the
winner, so it is pruned hard and costs less than the first. The winner is refined by the
correlative scan matcher.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from polynav.errors import ConfigError
from polynav.geometry import Pose2D
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
        theta_step: heading step of the search (over the whole circle).
        points: scan endpoints used (spread evenly over the scan).
        range_max: returns beyond this are not used (sparse, and long lever arms).
        min_score: a pose scoring below this (mean likelihood of the endpoints, 0..1) is no
            match.
        margin: the winner must beat every distinct alternative by this much.
        distinct_xy, distinct_theta: an alternative farther than this from the winner, in
            position or in heading, is distinct (one closer is the same answer, a cell or a
            few degrees off).
    """

    sigma: float = 0.1
    depth: int = 6
    theta_step: float = math.radians(0.75)
    points: int = 120
    range_max: float = 12.0
    min_score: float = 0.5
    margin: float = 0.08
    distinct_xy: float = 0.5
    distinct_theta: float = 0.3

    def __post_init__(self) -> None:
        for key in ("sigma", "theta_step", "range_max", "distinct_xy", "distinct_theta"):
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
        runner_up: the best distinct alternative's score when it is within two margins of the
            best (it is not searched for below that), else 0.
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
        self._info = info
        field = build_likelihood_field(grid, sigma=cfg.sigma, max_distance=4.0 * cfg.sigma)
        self._pre = branch_and_bound.precompute(field.likelihood, cfg.depth)
        # A robot stands in known free space; a cell of slack round it for the lattice.
        free = ndimage.binary_dilation(grid.data == 0, iterations=1)
        self._allowed = branch_and_bound.precompute(free.astype(np.float32), cfg.depth)
        self._matcher = ScanMatcher(build_likelihood_field(grid))
        self._polish = SearchWindow(xy=0.1, theta=math.radians(2.0),
                                    theta_step=math.radians(0.25))
        n_theta = max(1, int(round(2.0 * math.pi / cfg.theta_step)))
        self._thetas = -math.pi + (2.0 * math.pi / n_theta) * np.arange(n_theta, dtype=np.float64)
        self._centre = (0.5 * info.width, 0.5 * info.height)
        self._window = (max(info.width, info.height) + 1) // 2 + 1

    def locate(self, scan: LaserScan) -> Relocalization:
        """The robot's pose on the map from ``scan`` alone."""
        cfg, res = self.config, self._info.resolution
        points = self._points(scan)
        if points.shape[0] < 10:
            return Relocalization(None, 0.0, 0.0, "no match")
        cells = points / res
        cx, cy = self._centre
        best = branch_and_bound.search_headings(
            self._pre, cells, x=cx, y=cy, thetas=self._thetas, window_cells=self._window,
            min_score=0.5 * cfg.min_score, allowed=self._allowed,
        )
        if best is None:
            return Relocalization(None, 0.0, 0.0, "no match")
        if best.score < cfg.min_score:
            return Relocalization(None, best.score, 0.0, "no match")
        rival = branch_and_bound.search_headings(
            self._pre, cells, x=cx, y=cy, thetas=self._thetas, window_cells=self._window,
            min_score=best.score - 2.0 * cfg.margin, allowed=self._allowed,
            exclude=branch_and_bound.Exclusion(best.x, best.y, cfg.distinct_xy / res,
                                               best.theta, cfg.distinct_theta),
        )
        runner_up = 0.0 if rival is None else rival.score
        if best.score - runner_up < cfg.margin:
            log.info("relocalization ambiguous: %.3f against %.3f", best.score, runner_up)
            return Relocalization(None, best.score, runner_up, "ambiguous")
        # The search runs in the grid's frame; a map origin may be rotated (ROS allows it).
        pose = self._info.origin.compose(Pose2D(best.x * res, best.y * res, best.theta))
        refined = self._matcher.match(points, pose, self._polish).pose
        log.info("relocalized at %s (score %.3f, runner-up %.3f)", refined, best.score, runner_up)
        return Relocalization(refined, best.score, runner_up)

    def _points(self, scan: LaserScan) -> npt.NDArray[np.float64]:
        cfg = self.config
        points = scan_points(scan.ranges, scan.angles, range_min=0.05,
                             range_max=min(cfg.range_max, scan.range_max - 1e-6),
                             sensor_pose=scan.sensor_pose)
        if points.shape[0] > cfg.points:
            keep = np.linspace(0, points.shape[0] - 1, cfg.points).round().astype(np.int64)
            points = points[keep]
        return np.ascontiguousarray(points)
