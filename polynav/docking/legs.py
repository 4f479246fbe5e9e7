"""Find a cart (or a cabin) by its legs among a scan's points, near where it should stand.

A cart stands on four legs at the corners of a rectangle (``length`` along its heading,
``width`` across it); a cabin on four corner posts, which a lidar mounted low sees the same way
(:mod:`polynav.worlds.carts`). Where the cart stands is only known roughly (where it was left,
where the site says it is): the robot must drive in between its legs to within centimetres, so,
as for the charger (:mod:`polynav.docking.detector`), its pose is measured from the scan before
the final approach.

The search:

1. the points near the expected rectangle are grouped into **blobs** (neighbours within
   ``cluster_gap``); a blob no wider than a leg (``max_leg_size``) standing at least
   ``min_depth_step`` in front of the returns either side of it is a leg candidate, its
   centre the blob's centroid pushed away from the sensor by ``2 r / π`` (the centroid of the
   arc of a circle of radius ``r`` that a sensor sees);
2. each model leg (placed at the expected pose) takes the nearest candidate within
   ``search_radius``; with at least ``min_legs`` matched, the rigid transform that best maps the
   model's legs onto their matches (least squares, Kabsch in 2D) is the pose; the match and fit
   are repeated from that pose with ``match_distance``, so a wrong first match is corrected;
3. the fit is accepted when at least ``min_legs`` legs match within ``match_distance``, its RMS
   residual is below ``max_residual`` and the pose is within ``search_radius`` and
   ``search_angle`` of the expected one (a cart's rectangle is symmetric under a half turn: the
   expected heading picks the way in).

Everything is pure numpy: points in, a pose and the number of legs seen out, in whatever frame
the points are given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.errors import ConfigError
from polynav.geometry import Pose2D, angle_diff
from polynav.worlds.carts import leg_positions


@dataclass(frozen=True, slots=True)
class LegsConfig:
    """How far from the expected pose the cart is looked for, and what counts as found.

    Attributes:
        search_radius: the cart's centre may be this far [m] from the expected one (below half
            the legs' spacing, or a leg could be taken for its neighbour).
        search_angle: the cart may be turned this much [rad] either way.
        cluster_gap: points nearer [m] than this belong to one blob.
        max_leg_size: a blob wider [m] than this (beyond the leg's diameter) is not a leg.
        match_distance: a leg is matched within this distance [m] of the fitted model.
        max_residual: the fit's RMS residual [m], at most.
        min_legs: legs that must be seen (3: a cart is more than two posts).
        min_depth_step: a leg stands at least this much [m] in front of the returns beside it.
    """

    search_radius: float = 0.3
    search_angle: float = 0.4
    cluster_gap: float = 0.05
    max_leg_size: float = 0.04
    match_distance: float = 0.06
    max_residual: float = 0.025
    min_legs: int = 3
    min_depth_step: float = 0.1

    def __post_init__(self) -> None:
        for key in ("search_radius", "search_angle", "cluster_gap", "max_leg_size",
                    "match_distance", "max_residual", "min_depth_step"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value > 0.0):
                raise ConfigError(f"legs_detector.{key}", f"must be > 0, got {value!r}")
        if not 2 <= self.min_legs <= 4:
            raise ConfigError("legs_detector.min_legs", f"must be 2..4, got {self.min_legs}")


@dataclass(frozen=True, slots=True)
class LegsDetection:
    """The cart as seen: its pose (centre and heading, in the points' frame), how many legs
    carry the fit and their RMS residual [m]."""

    pose: Pose2D
    legs: int
    residual: float


def leg_candidates(points: npt.NDArray[np.float64], origin: tuple[float, float],
                   leg_radius: float, config: LegsConfig = LegsConfig()  # noqa: B008 - frozen
                   ) -> npt.NDArray[np.float64]:
    """(K, 2) centres of the leg-sized blobs among ``points`` (ordered as a scan's are, by
    angle), seen from the sensor at ``origin``."""
    if points.shape[0] == 0:
        return np.empty((0, 2), dtype=np.float64)
    bearing = np.arctan2(points[:, 1] - origin[1], points[:, 0] - origin[0])
    order = np.argsort(bearing)
    pts, bearing = points[order], bearing[order]
    turn = np.diff(bearing, append=bearing[0] + 2.0 * math.pi)  # to the next point's bearing
    step = float(np.median(turn)) if turn.shape[0] > 1 else math.pi
    gaps = np.hypot(*np.diff(pts, axis=0).T) > config.cluster_gap
    bounds = np.concatenate(([0], np.nonzero(gaps)[0] + 1, [pts.shape[0]]))
    dist = np.hypot(pts[:, 0] - origin[0], pts[:, 1] - origin[1])
    out = []
    n = pts.shape[0]
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        blob = pts[a:b]
        size = float(np.hypot(*(blob.max(axis=0) - blob.min(axis=0))))
        if size > 2.0 * leg_radius + config.max_leg_size:
            continue
        # A leg stands out in front of what is behind it: the beams either side of the blob
        # reach farther (a wall's stretch cut into blobs by sparse beams does not).
        # A beam beside it with no return (a gap in bearing) sees nothing nearer.
        near = float(dist[a:b].max()) + config.min_depth_step
        before, after = (a - 1) % n, b % n
        if turn[before] <= 1.5 * step and dist[before] < near:
            continue
        if turn[b - 1] <= 1.5 * step and dist[after] < near:
            continue
        cx, cy = blob.mean(axis=0)
        away = math.atan2(cy - origin[1], cx - origin[0])
        push = 2.0 * leg_radius / math.pi
        out.append((cx + push * math.cos(away), cy + push * math.sin(away)))
    return np.array(out, dtype=np.float64).reshape(-1, 2)


def find_legs(
    points: npt.NDArray[np.float64],
    origin: tuple[float, float],
    expected: Pose2D,
    length: float,
    width: float,
    leg_radius: float,
    config: LegsConfig = LegsConfig(),  # noqa: B008 - frozen
) -> LegsDetection | None:
    """The cart near ``expected`` (its centre and heading), or ``None`` if its legs are not
    there.

    Args:
        points: (N, 2) scan endpoints, in the frame of ``expected``.
        origin: the sensor's position in that frame.
        expected: where the cart should stand.
        length, width: the legs' rectangle [m] (between the legs' centres).
        leg_radius: a leg's radius [m].
        config: search window and acceptance.
    """
    reach = 0.5 * math.hypot(length, width) + config.search_radius + 0.1
    candidates = leg_candidates(points, origin, leg_radius, config)
    candidates = candidates[np.hypot(candidates[:, 0] - expected.x,
                                     candidates[:, 1] - expected.y) <= reach]
    if candidates.shape[0] < config.min_legs:
        return None
    pose = expected
    found: LegsDetection | None = None
    for radius in (config.search_radius, config.match_distance, config.match_distance):
        model = np.array(leg_positions(pose, length, width), dtype=np.float64)
        pairs = _match(model, candidates, radius)
        if len(pairs) < config.min_legs:
            return None
        local = np.array(leg_positions(Pose2D(), length, width), dtype=np.float64)
        src = local[[i for i, _ in pairs]]
        dst = candidates[[j for _, j in pairs]]
        pose = _fit(src, dst)
        moved = np.array(leg_positions(pose, length, width), dtype=np.float64)
        residual = float(np.sqrt(np.mean(np.sum((moved[[i for i, _ in pairs]] - dst) ** 2,
                                                axis=1))))
        found = LegsDetection(pose, len(pairs), residual)
    if found is None or found.residual > config.max_residual:
        return None
    if (found.pose.distance_to(expected) > config.search_radius
            or abs(angle_diff(found.pose.theta, expected.theta)) > config.search_angle):
        return None
    return found


def _match(model: npt.NDArray[np.float64], candidates: npt.NDArray[np.float64],
           radius: float) -> list[tuple[int, int]]:
    """Model leg i -> its nearest candidate j within ``radius``, each candidate used once."""
    d = np.hypot(model[:, None, 0] - candidates[None, :, 0],
                 model[:, None, 1] - candidates[None, :, 1])
    pairs: list[tuple[int, int]] = []
    used: set[int] = set()
    for flat in np.argsort(d, axis=None):
        i, j = divmod(int(flat), candidates.shape[0])
        if d[i, j] > radius:
            break
        if i in {p for p, _ in pairs} or j in used:
            continue
        pairs.append((i, j))
        used.add(j)
    return sorted(pairs)


def _fit(src: npt.NDArray[np.float64], dst: npt.NDArray[np.float64]) -> Pose2D:
    """The rigid transform (a pose) taking points ``src`` (model frame) onto ``dst``."""
    cs, cd = src.mean(axis=0), dst.mean(axis=0)
    a, b = src - cs, dst - cd
    sin = float(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]))
    cos = float(np.sum(a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]))
    theta = math.atan2(sin, cos)
    c, s = math.cos(theta), math.sin(theta)
    tx = cd[0] - (c * cs[0] - s * cs[1])
    ty = cd[1] - (s * cs[0] + c * cs[1])
    return Pose2D(float(tx), float(ty), theta)
