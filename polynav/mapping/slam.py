"""Online 2-D lidar SLAM: scan-to-submap matching, a pose graph, and loop closure.

The structure follows Cartographer (Hess et al., "Real-Time Loop Closure in 2D LIDAR SLAM",
ICRA 2016):

* **Nodes.** A scan becomes a pose-graph node once the robot has moved
  ``node_min_translation`` or turned ``node_min_rotation`` since the last node (the motion
  filter); every other scan just gets the last node's pose advanced by odometry.
* **Local SLAM.** A node's pose is predicted from the last node and the odometry since, then
  matched against the older of the two active submaps: a correlative, multi-resolution search
  (:class:`~polynav.localization.scan_matcher.ScanMatcher`, Olson 2009) and a Gauss-Newton
  refinement on the submap's likelihood field. The scan is then inserted into both active
  submaps (log-odds, :mod:`polynav.mapping.occupancy`).
* **Submaps.** Each submap is a rigid piece of map attached to its *anchor*, the node it was
  started at: its cells are in that node's frame, so moving the anchor moves the submap.
  A new submap starts every ``scans_per_submap`` nodes and each receives twice as many, so the
  one matched against always holds at least ``scans_per_submap`` scans.
* **Pose graph.** Edges tie each node to the previous one (odometry, weak), to the anchor of
  every submap it was inserted into (the local match, strong), and, for **loop closures**, to
  the anchor of an older finished submap it was found in by an exact branch-and-bound search
  (:mod:`polynav.mapping.branch_and_bound`) over a wide window, accepted above a score
  threshold and refined like a local match. The graph is optimised with a robust sparse
  least-squares solve (:mod:`polynav.mapping.pose_graph`) every ``optimize_every`` nodes when
  a loop closure came in, and once more at :meth:`Slam.finish`.
* **The map** is rendered at the end by inserting every node's scan at its optimised pose.
* **Updating a map.** Given a *prior* (a saved map to extend), node 0 is a virtual node at the
  map's frame, holding no scan, and the prior is a finished submap anchored there. The first
  scan's pose (where the robot was localized on the prior) is refined by a search in it, and
  every later node is searched for in it like in any old submap (it is always a candidate), so
  the new map keeps the prior's frame; the rendered map starts from the prior's cells
  (:meth:`~polynav.mapping.occupancy.LogOddsGrid.seeded`) and the new scans revise them.

:class:`Slam` does no I/O and reads no clock: it advances only on :meth:`Slam.add_scan`, so the
runtime can drive it on simulated or wall time, and the log tools can replay a log through it.
"""

from __future__ import annotations

import logging
import math
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.localization.likelihood_field import LikelihoodField, build_likelihood_field
from polynav.localization.scan_matcher import ScanMatcher, SearchWindow, scan_points
from polynav.localization.scan_matcher import warm_up as warm_up_matcher
from polynav.mapping import branch_and_bound
from polynav.mapping.config import SlamConfig
from polynav.mapping.logs import SensorLog
from polynav.mapping.occupancy import LogOddsGrid, log_odds
from polynav.mapping.occupancy import warm_up as warm_up_grid
from polynav.mapping.pose_graph import PoseGraph
from polynav.maps.map import Map

log = logging.getLogger(__name__)

# Finished submaps whose branch-and-bound grids are kept; older ones are rebuilt on demand
# (32 thrashed on a 40 x 25 m floor: a third of the loop-closure time went to rebuilding).
_PRECOMPUTED_CACHE = 256
# A prior map's cells start at this log-odds (about three contrary scans revise one).
_PRIOR_LEVEL = 1.5
# The cache key of the prior's branch-and-bound grids (submaps use their index).
_PRIOR_KEY = -1
# How far the start pose on a prior may be off, and how far a start not found in it is trusted.
_START_WINDOW_XY = 1.0
_START_WINDOW_THETA = math.radians(20.0)
_START_SIGMA = (0.2, 0.2, 0.1)


@dataclass(frozen=True, slots=True, eq=False)
class _Node:
    stamp: float
    odom: Pose2D
    points: npt.NDArray[np.float64]
    match_points: npt.NDArray[np.float64]
    sensor: npt.NDArray[np.float64]


@dataclass(slots=True, eq=False)
class _Rendered:
    """The grid :meth:`Slam.render_map` built, from the first ``nodes`` nodes at ``poses``
    (the graph's pose list then: an optimisation replaces it)."""

    poses: list[tuple[float, float, float]]
    grid: LogOddsGrid
    nodes: int = 0


class _Submap:
    """A log-odds grid in its anchor node's frame, and the matchers built from it."""

    def __init__(self, anchor: int, config: SlamConfig, grid: LogOddsGrid | None = None) -> None:
        self.anchor = anchor
        self.grid = grid or LogOddsGrid(config.resolution, hit=log_odds(config.hit_probability),
                                        miss=log_odds(config.miss_probability))
        self.scans = 0
        self.finished = False
        self.centre_sum = np.zeros(2)
        self._config = config
        self._field: LikelihoodField | None = None
        self._matcher: ScanMatcher | None = None
        self._built_at = 0

    @property
    def centre(self) -> npt.NDArray[np.float64]:
        """Mean position of the scans inserted, anchor frame [m]."""
        return self.centre_sum / max(self.scans, 1)

    def insert(self, local: Pose2D, node: _Node) -> None:
        self.grid.insert(local, node.points, node.sensor)
        self.scans += 1
        self.centre_sum += (local.x, local.y)

    def finish(self) -> None:
        """No more scans: the next matcher is built from every scan, and kept."""
        self.finished = True
        self._matcher = None

    def matcher(self) -> ScanMatcher:
        # Rebuilding the field costs two distance transforms; a submap that already holds many
        # scans changes little with one more, so it is rebuilt less often as it fills.
        stale = not self.finished and self.scans - self._built_at >= max(1, self._built_at // 4)
        if self._matcher is None or stale:
            c = self._config
            grid = self.grid.to_map(occupied=log_odds(c.occupied_probability),
                                    free=log_odds(c.free_probability))
            self._field = build_likelihood_field(grid, sigma=c.likelihood_sigma, centres=True)
            self._matcher = ScanMatcher(self._field)
            self._built_at = self.scans
        return self._matcher

    @property
    def field(self) -> LikelihoodField:
        self.matcher()
        assert self._field is not None
        return self._field


class Slam:
    """Incremental SLAM over scans and odometry (see the module docstring).

    Args:
        config: all parameters.
        prior: a saved map to extend (see "Updating a map" in the module docstring); the poses
            are then in its frame, and the first scan's odometry pose must be the robot's pose
            on it (within about a metre and 20°).

    Raises:
        ValueError: the prior's resolution is not the configured one, or its origin is rotated.
    """

    def __init__(self, config: SlamConfig | None = None, *, prior: Map | None = None) -> None:
        self.config = config or SlamConfig()
        self.graph = PoseGraph()
        self._prior: _Submap | None = None
        self._prior_map = prior
        self._nodes: list[_Node] = []
        self._submaps: list[_Submap] = []
        self._active: list[_Submap] = []
        self._scan_node: list[int] = []
        self._scan_delta: list[Pose2D] = []
        self._precomputed: OrderedDict[int, branch_and_bound.PrecomputedGrids] = OrderedDict()
        self._since_optimize = 0
        self._new_loops = 0
        self._untied = 0.0  # [m] travelled since the last loop closure
        self.loop_closures = 0
        self.rejected_loop_closures = 0
        self.failed_matches = 0
        c = self.config
        self._window = SearchWindow(xy=c.match_window_xy, theta=c.match_window_theta,
                                    theta_step=c.match_theta_step, coarse=True)
        self._polish = SearchWindow(xy=c.resolution, theta=c.loop_theta_step,
                                    theta_step=0.25 * c.loop_theta_step)
        self.prior_matches = 0
        self._rendered: _Rendered | None = None
        if prior is not None:
            if abs(prior.info.resolution - c.resolution) > 1e-9:
                raise ValueError(f"the map to extend has {prior.info.resolution} m cells, the "
                                 f"SLAM {c.resolution} m")
            self._prior = _Submap(0, c, self._seeded(prior))
            self._prior.finish()
            empty = np.zeros((0, 2))
            self._nodes.append(_Node(-math.inf, Pose2D(), empty, empty, np.zeros(2)))
            self.graph.add_node(0.0, 0.0, 0.0)
        # The index of the first real node (1 after a prior's virtual node).
        self._base = len(self._nodes)

    # -- input ----------------------------------------------------------------------------------

    def add_scan(
        self,
        odom: Pose2D,
        ranges: npt.NDArray[np.floating],
        angles: npt.NDArray[np.float64],
        t: float,
        *,
        sensor_pose: Pose2D | None = None,
    ) -> Pose2D:
        """Take one scan with the odometry pose at its time; returns the robot's pose estimate.

        Args:
            odom: odometry pose at ``t`` (odometry frame; only its changes are used).
            ranges: (N,) distances [m]; non-finite or out of range means no return.
            angles: (N,) beam angles [rad] in the sensor frame.
            t: the scan's time [s].
            sensor_pose: the sensor's mount in the robot frame (default: at the robot centre).

        Returns:
            The pose in the map frame (the frame of the first scan's odometry pose).
        """
        c = self.config
        mount = sensor_pose or Pose2D()
        if len(self._nodes) > self._base:
            last = len(self._nodes) - 1
            delta = odom.relative_to(self._nodes[last].odom)
            if (math.hypot(delta.x, delta.y) < c.node_min_translation
                    and abs(delta.theta) < c.node_min_rotation):
                self._scan_node.append(last)
                self._scan_delta.append(delta)
                return self._pose(last).compose(delta)
        points = scan_points(ranges, np.asarray(angles, dtype=np.float64), range_min=c.range_min,
                             range_max=c.range_max, sensor_pose=mount)
        step = max(1, int(math.ceil(points.shape[0] / c.match_points)))
        node = _Node(float(t), odom, points, np.ascontiguousarray(points[::step]),
                     np.array([mount.x, mount.y]))
        pose = self._add_node(node)
        self._scan_node.append(len(self._nodes) - 1)
        self._scan_delta.append(Pose2D())
        return pose

    def finish(self) -> None:
        """Optimise the whole graph one last time (call after the last scan)."""
        if len(self._nodes) > 1:
            self._optimize(max_nfev=200)

    # -- output ---------------------------------------------------------------------------------

    @property
    def node_count(self) -> int:
        """Nodes made of scans (a prior's virtual node not counted)."""
        return len(self._nodes) - self._base

    @property
    def submap_count(self) -> int:
        return len(self._submaps)

    def trajectory(self) -> list[Pose2D]:
        """The pose of every scan taken so far, in order, from the current graph."""
        return [self._pose(k).compose(d)
                for k, d in zip(self._scan_node, self._scan_delta, strict=True)]

    def render_map(self) -> Map:
        """The occupancy map of every node's scan at its current pose (100 / 0 / -1).

        The log-odds grid is kept between calls: while the graph has not been optimised since
        (its pose list is the same object, only appended to), only the nodes added since are
        inserted, which gives the very grid a full render would (the same inserts in the same
        order). An exploration renders the live map at every replan; rendering every node
        each time cost as much as the rest of the SLAM on a whole floor."""
        c = self.config
        rendered = self._rendered
        if rendered is None or rendered.poses is not self.graph.poses:
            if self._prior_map is not None:
                grid = self._seeded(self._prior_map)
            else:
                grid = LogOddsGrid(c.resolution, hit=log_odds(c.hit_probability),
                                   miss=log_odds(c.miss_probability))
            rendered = self._rendered = _Rendered(self.graph.poses, grid)
        for k in range(rendered.nodes, len(self._nodes)):
            node = self._nodes[k]
            rendered.grid.insert(self._pose(k), node.points, node.sensor)
        rendered.nodes = len(self._nodes)
        return rendered.grid.to_map(occupied=log_odds(c.occupied_probability),
                                    free=log_odds(c.free_probability))

    # -- internals ------------------------------------------------------------------------------

    def _pose(self, k: int) -> Pose2D:
        return Pose2D(*self.graph.poses[k])

    def _seeded(self, prior: Map) -> LogOddsGrid:
        c = self.config
        return LogOddsGrid.seeded(prior, hit=log_odds(c.hit_probability),
                                  miss=log_odds(c.miss_probability), level=_PRIOR_LEVEL)

    def _add_node(self, node: _Node) -> Pose2D:
        c = self.config
        index = len(self._nodes)
        start_found: Pose2D | None = None
        if index == self._base:
            pose = node.odom
            if self._prior is not None and node.match_points.shape[0] > 0:
                start_found = self._find_in_submap(
                    _PRIOR_KEY, self._prior, node, pose, window_xy=_START_WINDOW_XY,
                    window_theta=_START_WINDOW_THETA)
                if start_found is None:
                    log.warning("the first scan is not found on the map being extended near "
                                "%s: the start pose is trusted as given", pose)
                pose = start_found or pose
        else:
            prev = self._nodes[index - 1]
            delta = node.odom.relative_to(prev.odom)
            guess = self._pose(index - 1).compose(delta)
            target = self._active[0]
            anchor = self._pose(target.anchor)
            local = guess.relative_to(anchor)
            if node.match_points.shape[0] > 0:
                match = target.matcher().match(node.match_points, local, self._window,
                                               prior_xy=c.match_prior_xy,
                                               prior_theta=c.match_prior_theta)
                if match.score >= c.match_min_score:
                    local = match.pose
                else:
                    self.failed_matches += 1
            pose = anchor.compose(local)
        self._nodes.append(node)
        self.graph.add_node(pose.x, pose.y, pose.theta)
        if index == self._base and self._prior is not None:
            # Tie the first node to the prior's frame (node 0): found there, or as told.
            sigma = ((c.loop_sigma_xy, c.loop_sigma_xy, c.loop_sigma_theta)
                     if start_found is not None else _START_SIGMA)
            self.graph.add_edge(0, index, (pose.x, pose.y, pose.theta), sigma)
        if index > self._base:
            dist = math.hypot(delta.x, delta.y)
            sxy = max(c.resolution, c.odom_sigma_xy * dist)
            self.graph.add_edge(index - 1, index, (delta.x, delta.y, delta.theta),
                                (sxy, sxy, c.odom_sigma_theta + 0.1 * abs(delta.theta)))
            self._untied += dist
        if not self._submaps or self._submaps[-1].scans >= c.scans_per_submap:
            submap = _Submap(index, c)
            self._submaps.append(submap)
            self._active.append(submap)
        for submap in self._active:
            local = pose.relative_to(self._pose(submap.anchor))
            submap.insert(local, node)
            if submap.anchor != index:
                self.graph.add_edge(submap.anchor, index, (local.x, local.y, local.theta),
                                    (c.match_sigma_xy, c.match_sigma_xy, c.match_sigma_theta))
        if self._active[0].scans >= 2 * c.scans_per_submap:
            done = self._active.pop(0)
            done.finish()
        if index % c.loop_node_stride == 0:
            self._close_loops(index)
        self._since_optimize += 1
        # A solve costs in proportion to the graph: on a long run, solving every
        # ``optimize_every`` nodes would cost quadratically; every tenth of the graph keeps it
        # linear (the live pose is the local SLAM's meanwhile, the final solve is complete).
        every = max(c.optimize_every, (len(self._nodes) - self._base) // 10)
        if self._new_loops and self._since_optimize >= every:
            self._optimize(max_nfev=50)
        return self._pose(index)

    def _close_loops(self, index: int) -> None:
        c = self.config
        node = self._nodes[index]
        if node.match_points.shape[0] == 0:
            return
        pose = self._pose(index)
        found = 0
        if self._prior is not None:
            # The prior is searched first: it holds the frame the new map must keep.
            local = self._find_in_submap(_PRIOR_KEY, self._prior, node, pose)
            if local is not None:
                self._tie(0, index, local)
                self.prior_matches += 1
                found += 1
        window = min(c.loop_window_xy, c.loop_window_min_xy + c.loop_window_growth * self._untied)
        # Submaps started just before this node are tied to it through the local chain already.
        recent = index - 4 * c.scans_per_submap
        candidates = []
        for s, submap in enumerate(self._submaps):
            if not submap.finished or submap.anchor >= recent:
                continue
            centre = self._pose(submap.anchor).transform_point(*submap.centre)
            distance = math.hypot(centre[0] - pose.x, centre[1] - pose.y)
            if distance <= c.loop_max_distance:
                candidates.append((distance, s))
        for _, s in sorted(candidates):
            if found >= c.loop_max_per_node:
                break
            submap = self._submaps[s]
            anchor = self._pose(submap.anchor)
            local = self._find_in_submap(s, submap, node, pose.relative_to(anchor),
                                         window_xy=window)
            if local is None:
                continue
            self._tie(submap.anchor, index, local)
            self.loop_closures += 1
            found += 1

    def _tie(self, anchor: int, index: int, local: Pose2D) -> None:
        """A loop-closure edge from node ``anchor`` (a submap's, or the prior's node 0) to node
        ``index`` found at ``local``: robust, solved at the next optimisation, and the drift
        the loop search must cover starts again from nothing."""
        c = self.config
        self.graph.add_edge(anchor, index, (local.x, local.y, local.theta),
                            (c.loop_sigma_xy, c.loop_sigma_xy, c.loop_sigma_theta), robust=True)
        self._new_loops += 1
        self._untied = 0.0

    def _find_in_submap(self, s: int, submap: _Submap, node: _Node, guess: Pose2D, *,
                        window_xy: float | None = None,
                        window_theta: float | None = None) -> Pose2D | None:
        c = self.config
        field = submap.field
        pre = self._precomputed.get(s)
        if pre is None:
            pre = branch_and_bound.precompute(field.likelihood, c.loop_depth)
            self._precomputed[s] = pre
            if len(self._precomputed) > _PRECOMPUTED_CACHE:
                self._precomputed.popitem(last=False)
        else:
            self._precomputed.move_to_end(s)
        res = c.resolution
        origin = field.info.origin
        found = branch_and_bound.search(
            pre, node.match_points / res,
            x=(guess.x - origin.x) / res, y=(guess.y - origin.y) / res, theta=guess.theta,
            window_cells=int(math.ceil((window_xy or c.loop_window_xy) / res)),
            window_theta=window_theta or c.loop_window_theta, theta_step=c.loop_theta_step,
            min_score=c.loop_min_score,
        )
        if found is None:
            return None
        coarse = Pose2D(origin.x + found.x * res, origin.y + found.y * res, found.theta)
        match = submap.matcher().match(node.match_points, coarse, self._polish)
        if match.score < c.loop_min_score:
            return None
        log.debug("loop closure: node %d in submap %d, score %.3f", len(self._nodes) - 1, s,
                  match.score)
        return match.pose

    def _optimize(self, *, max_nfev: int) -> None:
        c = self.config
        self.rejected_loop_closures += self.graph.optimize(huber_scale=c.huber_scale,
                                                           max_nfev=max_nfev)
        self._since_optimize = 0
        self._new_loops = 0


def replay(log: SensorLog, config: SlamConfig | None = None) -> Slam:
    """Run the SLAM over every scan of a log, then :meth:`Slam.finish` it."""
    slam = Slam(config)
    for scan in log.scans:
        slam.add_scan(scan.odom, scan.ranges, scan.angles, scan.stamp,
                      sensor_pose=scan.sensor_pose)
    slam.finish()
    return slam


def warm_up() -> None:
    """Compile every numba kernel the SLAM uses, so timing starts at the steady state."""
    warm_up_matcher()
    warm_up_grid()
    branch_and_bound.warm_up()
