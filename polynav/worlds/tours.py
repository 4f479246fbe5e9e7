"""Closed tours through a floor plan, for recording SLAM logs the SLAM was never tuned on.

The SLAM's defaults were tuned on Intel and on the demo site; to know whether they generalise,
:mod:`polynav.robot.sim.recording` drives the simulator on plans shipped in ``data/`` that were
never looked at while tuning. A tour here is what that drive follows: ``stops`` of the points
:func:`~polynav.worlds.from_map.plan_world` places (each ``robot_radius + margin`` from walls, in
the region the robot can reach), ordered by nearest neighbour from the start, every leg planned
by :class:`~polynav.planning.grid_planner.GridPlanner` on the static costmap of the plan (so the
chauffeur, which steers straight from waypoint to waypoint, keeps clear of walls), and back to
the start, so a SLAM that does not close the loop shows it. The path is downsampled to
waypoints about ``spacing`` apart, always keeping the path's corners.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

from polynav.errors import InvalidRequest, PolynavError
from polynav.geometry import Pose2D
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.planning.grid_planner import GridPlanner, GridPlannerConfig
from polynav.worlds.from_map import FromMapOptions, load_plan, plan_world, to_world
from polynav.worlds.world import World


@dataclass(frozen=True, slots=True)
class Tour:
    """A world built from a plan and a closed tour through it (world frame, metres).

    Attributes:
        world: the simulated world (no walkers: a SLAM score must not depend on who walked by).
        stops: the planned points visited, in order, the start first and last.
        waypoints: the downsampled path through them, first and last equal.
        length: the path's length [m].
    """

    world: World
    stops: tuple[tuple[float, float], ...]
    waypoints: tuple[tuple[float, float], ...]
    length: float


def plan_tour(
    plan: str | Path,
    *,
    stops: int = 7,
    seed: int = 0,
    cell: float = 1.0,
    spacing: float = 0.75,
    point_spacing: float = 3.0,
    robot_radius: float = 0.25,
) -> Tour:
    """Build the world of ``plan`` and a closed tour of ``stops`` of its points.

    Args:
        plan: a ROS map (``.yaml``) or a MovingAI map (``.map``).
        stops: points visited besides the start (fewer on a plan too small for them).
        seed: places the points (:class:`~polynav.worlds.from_map.FromMapOptions`).
        cell: metres per MovingAI cell.
        spacing: waypoints lie about this far apart along the path [m].
        point_spacing: the points lie at least this far apart [m].
        robot_radius: the simulated robot's radius [m] (the simulator's default).

    Raises:
        InvalidRequest: as :func:`~polynav.worlds.from_map.load_plan` and ``plan_world``;
            ``stops`` < 2 or ``spacing`` not > 0; a leg the planner finds no path for.
    """
    if stops < 2:
        raise InvalidRequest("stops", f"a tour needs at least 2 stops, got {stops}")
    if not (math.isfinite(spacing) and spacing > 0.0):
        raise InvalidRequest("spacing", f"must be finite and > 0, got {spacing}")
    options = FromMapOptions(cell=cell, points=stops, walkers=0, seed=seed,
                             robot_radius=robot_radius, margin=0.35,
                             point_spacing=point_spacing)
    planned = plan_world(Path(plan).stem, load_plan(plan, options), options, allow_fewer=True)
    world = to_world(planned, options)
    order = _nearest_neighbour([planned.start[:2], *(p[:2] for p in planned.points)])
    costmap = Costmap.from_map(planned.grid, CostmapConfig(
        robot_radius=robot_radius, inflation_radius=robot_radius + 0.6, obstacle_layer=False))
    planner = GridPlanner(GridPlannerConfig())
    path: list[npt.NDArray[np.float64]] = []
    for (ax, ay), (bx, by) in zip(order[:-1], order[1:], strict=True):
        try:
            leg = planner.plan(costmap, Pose2D(ax, ay, 0.0), Pose2D(bx, by, 0.0))
        except PolynavError as exc:
            raise InvalidRequest("plan", f"{plan}: no path from ({ax:.2f}, {ay:.2f}) to "
                                 f"({bx:.2f}, {by:.2f}): {exc}") from exc
        points = leg.points if not path else leg.points[1:]
        path.append(np.asarray(points, dtype=np.float64))
    polyline = np.vstack(path)
    # The tour ends exactly where it began (the planner may stop within its goal tolerance).
    polyline = np.vstack([polyline, polyline[:1]])
    waypoints = _downsample(polyline, spacing)
    length = float(np.sum(np.hypot(*np.diff(polyline, axis=0).T)))
    return Tour(world, tuple(order), waypoints, length)


def _nearest_neighbour(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The points as a closed tour by nearest neighbour from the first (start first and last)."""
    rest = list(points[1:])
    tour = [points[0]]
    while rest:
        x, y = tour[-1]
        k = min(range(len(rest)), key=lambda i: math.hypot(rest[i][0] - x, rest[i][1] - y))
        tour.append(rest.pop(k))
    tour.append(points[0])
    return [(float(x), float(y)) for x, y in tour]


def _downsample(
    polyline: npt.NDArray[np.float64], spacing: float, tolerance: float = 0.1
) -> tuple[tuple[float, float], ...]:
    """Points of the path about ``spacing`` apart, each chord within ``tolerance`` [m] of the
    path it replaces (a corner is kept rather than cut towards a wall); the last point always."""
    keep = [0]
    n = polyline.shape[0]
    while keep[-1] < n - 1:
        a = keep[-1]
        best = a + 1
        travelled = 0.0
        for b in range(a + 1, n):
            travelled += float(np.hypot(*(polyline[b] - polyline[b - 1])))
            if travelled > spacing or _deviation(polyline, a, b) > tolerance:
                break
            best = b
        keep.append(best)
    return tuple((float(polyline[k, 0]), float(polyline[k, 1])) for k in keep)


def _deviation(polyline: npt.NDArray[np.float64], a: int, b: int) -> float:
    """How far [m] the path's points between ``a`` and ``b`` lie from the chord a-b."""
    if b - a < 2:
        return 0.0
    chord = polyline[b] - polyline[a]
    norm = float(np.hypot(*chord))
    rel = polyline[a + 1:b] - polyline[a]
    if norm < 1e-9:
        return float(np.max(np.hypot(rel[:, 0], rel[:, 1])))
    return float(np.max(np.abs(chord[0] * rel[:, 1] - chord[1] * rel[:, 0])) / norm)
