"""Find the charger's plate among a scan's points, near where the marker says it is.

The site's charger point (the marker) is only where someone put it: a few centimetres and
degrees off the real charger is common, and that is more than the contacts forgive. As Nav2's
docking server refines a dock's pose from perception before the final approach, the dock phase
asks this detector where the plate really is.

The search has two stages. A coarse one scores a grid of face poses around the expected one
(``search_radius`` [m] and ``search_angle`` [rad] either way) by how many points lie on the
plate's outline (:class:`~polynav.docking.shape.DockShape`), all candidates at once in numpy. The
best few are then refined by point-to-line ICP (Gauss-Newton on the outline's segments) and
verified:

- each flank of the notch carries ``min_flank_points`` points spread over at least
  ``min_flank_cover`` of its length (the notch is what a wall, a post or a box lacks; a wing
  may be hidden: a partial view still counts);
- few points contradict the plate: a point across the plate's width that lies in front of its
  surface (in free space the plate would fill with nothing) or behind it (where the plate would
  hide it) is evidence against it. ``quality`` is the share of inliers among inliers and
  contradictions; below ``min_quality`` the shape is not the dock.

While the robot approaches, :func:`refine_dock` re-detects from the last pose (ICP and the same
verification only), which is cheap enough for every scan. Everything is pure numpy: points in,
a pose and its quality out, in whatever frame the points are given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.docking.shape import DockShape
from polynav.errors import ConfigError
from polynav.geometry import Pose2D, angle_diff
from polynav.robot.interface import LaserScan

_DAMPING = 1e-6


@dataclass(frozen=True, slots=True)
class DetectorConfig:
    """How far from the expected pose the plate is looked for, and what counts as found.

    Attributes:
        search_radius: the face's centre may be this far [m] from the expected one.
        search_angle: the face may be turned this much [rad] either way.
        grid_step: the coarse search's step [m]; angles step ``grid_step`` over the plate's
            half width.
        inlier_distance: a point this near [m] the outline lies on it.
        min_flank_points: points each flank of the notch must carry.
        min_flank_cover: share of each flank's length its points must span.
        min_quality: inliers over inliers and contradicting points, at least.
        candidates: how many of the coarse search's best poses are refined.
    """

    search_radius: float = 0.3
    search_angle: float = 0.35
    grid_step: float = 0.04
    inlier_distance: float = 0.025
    min_flank_points: int = 4
    min_flank_cover: float = 0.5
    min_quality: float = 0.8
    candidates: int = 4

    def __post_init__(self) -> None:
        for key in ("search_radius", "search_angle", "grid_step", "inlier_distance",
                    "min_flank_cover", "min_quality"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value > 0.0):
                raise ConfigError(f"dock_detector.{key}", f"must be > 0, got {value!r}")
        if self.min_flank_cover > 1.0 or self.min_quality > 1.0:
            raise ConfigError("dock_detector", "min_flank_cover and min_quality are shares <= 1")
        if self.min_flank_points < 2 or self.candidates < 1:
            raise ConfigError("dock_detector", "min_flank_points >= 2 and candidates >= 1")


@dataclass(frozen=True, slots=True)
class DockDetection:
    """The plate as seen: its face pose (in the points' frame), the share of supporting points
    among the points that speak to it (``quality``, 0..1), the inliers' RMS distance to the
    outline [m] and their number."""

    pose: Pose2D
    quality: float
    residual: float
    inliers: int


def points_of_scan(scan: LaserScan, pose: Pose2D) -> npt.NDArray[np.float64]:
    """(N, 2) endpoints of ``scan``'s valid returns in the frame of ``pose`` (the robot's pose
    in it, e.g. the map frame)."""
    r = np.asarray(scan.ranges, dtype=np.float64)
    ok = np.isfinite(r) & (r >= scan.range_min) & (r <= scan.range_max)
    sensor = pose.compose(scan.sensor_pose)
    a = scan.angles[ok] + sensor.theta
    r = r[ok]
    return np.stack((sensor.x + r * np.cos(a), sensor.y + r * np.sin(a)), axis=1)


def find_dock(
    points: npt.NDArray[np.float64],
    expected: Pose2D,
    shape: DockShape,
    config: DetectorConfig = DetectorConfig(),  # noqa: B008 - frozen
) -> DockDetection | None:
    """The plate near ``expected`` (its face pose), or ``None`` if no such shape is there.

    Args:
        points: (N, 2) scan endpoints, in the frame of ``expected``.
        expected: where the face should be (from the marker).
        shape: the plate's outline.
        config: search window and acceptance.
    """
    near = _window(points, expected, shape, config.search_radius)
    if near.shape[0] < 2 * config.min_flank_points:
        return None
    starts = _coarse(near, expected, shape, config)
    best: DockDetection | None = None
    for start in starts:
        found = _refined(near, start, expected, shape, config)
        if found is not None and (best is None or _rank(found) > _rank(best)):
            best = found
    return best


def refine_dock(
    points: npt.NDArray[np.float64],
    guess: Pose2D,
    shape: DockShape,
    config: DetectorConfig = DetectorConfig(),  # noqa: B008 - frozen
    *,
    expected: Pose2D | None = None,
) -> DockDetection | None:
    """The plate re-detected from ``guess`` (the last detection): ICP and verification only.

    ``expected`` (default ``guess``) bounds the answer by the search window as
    :func:`find_dock` does.
    """
    near = _window(points, guess, shape, config.inlier_distance * 4.0)
    if near.shape[0] < 2 * config.min_flank_points:
        return None
    return _refined(near, guess, expected or guess, shape, config)


# -- internals -------------------------------------------------------------------------------


def _rank(d: DockDetection) -> float:
    return d.quality * d.inliers


def _window(points: npt.NDArray[np.float64], centre: Pose2D, shape: DockShape,
            margin: float) -> npt.NDArray[np.float64]:
    """The points within reach of the plate round ``centre`` (its half width, its depth and
    ``margin``)."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    reach = math.hypot(0.5 * shape.width, shape.notch_depth) + margin + 0.05
    d2 = (pts[:, 0] - centre.x) ** 2 + (pts[:, 1] - centre.y) ** 2
    return pts[d2 <= reach * reach]


def _local(points: npt.NDArray[np.float64], x: npt.NDArray[np.float64],
           y: npt.NDArray[np.float64], theta: npt.NDArray[np.float64]
           ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Points in the face frames of K poses: (K, N) arrays u (into the dock), v (left)."""
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    dx = points[None, :, 0] - x[:, None]
    dy = points[None, :, 1] - y[:, None]
    return c * dx + s * dy, -s * dx + c * dy


def _segment_distances(u: npt.NDArray[np.float64], v: npt.NDArray[np.float64],
                       shape: DockShape) -> npt.NDArray[np.float64]:
    """(..., 4) distance of each local point to each segment of the outline."""
    seg = shape.segments()
    ax, ay = seg[:, 0], seg[:, 1]
    ex, ey = seg[:, 2] - ax, seg[:, 3] - ay
    length2 = ex * ex + ey * ey
    qx, qy = u[..., None] - ax, v[..., None] - ay
    t = np.clip((qx * ex + qy * ey) / length2, 0.0, 1.0)
    return np.hypot(qx - t * ex, qy - t * ey)


def _coarse(points: npt.NDArray[np.float64], expected: Pose2D, shape: DockShape,
            config: DetectorConfig) -> list[Pose2D]:
    """The best few face poses of a grid round ``expected``, by soft inlier count."""
    step = config.grid_step
    n = int(math.ceil(config.search_radius / step))
    offsets = np.arange(-n, n + 1) * step
    angle_step = step / (0.5 * shape.width)
    m = int(math.ceil(config.search_angle / angle_step))
    turns = np.arange(-m, m + 1) * angle_step
    gx, gy, gt = np.meshgrid(offsets, offsets, turns, indexing="ij")
    keep = np.hypot(gx, gy) <= config.search_radius + 1e-9
    gx, gy, gt = gx[keep], gy[keep], gt[keep]
    c, s = math.cos(expected.theta), math.sin(expected.theta)
    x = expected.x + c * gx - s * gy
    y = expected.y + s * gx + c * gy
    theta = expected.theta + gt
    u, v = _local(points, x, y, theta)
    d = _segment_distances(u, v, shape).min(axis=-1)
    tol = step
    score = np.clip(1.0 - (d / tol) ** 2, 0.0, None).sum(axis=1)
    # Contradictions: points across the plate in front of its surface or behind it.
    across = np.abs(v) < 0.5 * shape.width
    off = across & (d > tol)
    score -= off.sum(axis=1)
    order = np.argsort(-score)[: config.candidates]
    return [Pose2D(float(x[k]), float(y[k]), float(theta[k])) for k in order]


def _refined(points: npt.NDArray[np.float64], start: Pose2D, expected: Pose2D,
             shape: DockShape, config: DetectorConfig) -> DockDetection | None:
    """ICP from ``start``, then the verification of the module docstring."""
    pose = _icp(points, start, shape, config)
    if pose is None:
        return None
    if (math.hypot(pose.x - expected.x, pose.y - expected.y) > config.search_radius + 1e-9
            or abs(angle_diff(pose.theta, expected.theta)) > config.search_angle + 1e-9):
        return None
    return _verified(points, pose, shape, config)


def _icp(points: npt.NDArray[np.float64], start: Pose2D, shape: DockShape,
         config: DetectorConfig) -> Pose2D | None:
    seg = shape.segments()
    ex, ey = seg[:, 2] - seg[:, 0], seg[:, 3] - seg[:, 1]
    length = np.hypot(ex, ey)
    nx, ny = -ey / length, ex / length  # unit normals of the segments
    offset = nx * seg[:, 0] + ny * seg[:, 1]
    pose = start
    gates = (3.0, 3.0, 2.0, 2.0) + (1.5,) * 8
    for gate in gates:
        u, v = _local(points, np.array([pose.x]), np.array([pose.y]), np.array([pose.theta]))
        u, v = u[0], v[0]
        dist = _segment_distances(u, v, shape)
        which = np.argmin(dist, axis=1)
        near = dist[np.arange(dist.shape[0]), which] <= gate * config.inlier_distance
        if np.count_nonzero(near) < 3:
            return None
        qu, qv, k = u[near], v[near], which[near]
        a, b = nx[k], ny[k]
        # residual a*(u') + b*(v') - c for u' = u - dth*v + du, v' = v + dth*u + dv
        r = a * qu + b * qv - offset[k]
        jac = np.stack((a, b, a * -qv + b * qu), axis=1)
        h = jac.T @ jac + _DAMPING * np.eye(3)
        step = np.linalg.solve(h, -jac.T @ r)
        du, dv, dth = (float(step[0]), float(step[1]), float(step[2]))
        # The correction moves points in the face frame: the face moves by its inverse.
        correction = Pose2D(du, dv, dth)
        pose = pose.compose(correction.inverse())
        if abs(du) < 1e-5 and abs(dv) < 1e-5 and abs(dth) < 1e-5 and gate <= 1.5:
            break
    return pose


def _verified(points: npt.NDArray[np.float64], pose: Pose2D, shape: DockShape,
              config: DetectorConfig) -> DockDetection | None:
    u, v = _local(points, np.array([pose.x]), np.array([pose.y]), np.array([pose.theta]))
    u, v = u[0], v[0]
    dist = _segment_distances(u, v, shape)
    which = np.argmin(dist, axis=1)
    best = dist[np.arange(dist.shape[0]), which]
    tol = config.inlier_distance
    inlier = best <= tol
    across = np.abs(v) < 0.5 * shape.width - tol
    contradicting = across & ~inlier & (np.abs(u - shape.depth_at(v)) > tol)
    half = 0.5 * shape.notch_width
    for flank in (1, 2):
        on = inlier & (which == flank)
        if np.count_nonzero(on) < config.min_flank_points:
            return None
        span = float(np.ptp(v[on]))
        if span < config.min_flank_cover * half:
            return None
    inliers = int(np.count_nonzero(inlier))
    quality = inliers / (inliers + int(np.count_nonzero(contradicting)))
    if quality < config.min_quality:
        return None
    residual = float(np.sqrt(np.mean(best[inlier] ** 2)))
    return DockDetection(pose, quality, residual, inliers)
