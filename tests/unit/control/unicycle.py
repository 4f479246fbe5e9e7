"""A tiny exact unicycle simulation and cost-grid snapshots for the controller tests.

The robot moves exactly on the commanded arc for each period (no slip, no lag), so every deviation
the tests see is the controller's own. The velocity fed back to the controller is the last
command, which the exact base achieved.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from polynav.control.interface import Controller, ControlStatus
from polynav.geometry import Pose2D, Twist
from polynav.maps import costs
from polynav.maps.map import MapInfo
from polynav.planning.path import Path

DT = 0.05


@dataclass(frozen=True)
class Grid:
    """A frozen costmap snapshot (what ``CostGrid`` asks for)."""

    info: MapInfo
    costs: npt.NDArray[np.uint8]


def empty_grid(size_m: float = 20.0, resolution: float = 0.05) -> Grid:
    """An all-FREE grid of ``size_m`` square, centred on the origin."""
    n = round(size_m / resolution)
    info = MapInfo(resolution, n, n, Pose2D(-size_m / 2, -size_m / 2, 0.0))
    return Grid(info, np.zeros((n, n), dtype=np.uint8))


def with_disc(grid: Grid, x: float, y: float, radius: float, *, inscribed: float,
              inflation: float = 0.0) -> Grid:
    """A copy of ``grid`` with a round obstacle: LETHAL within ``radius`` of (x, y), INSCRIBED
    within ``radius + inscribed``, and a decaying inflation cost out to ``radius + inflation``."""
    info = grid.info
    iy, ix = np.mgrid[0 : info.height, 0 : info.width]
    centres = info.cells_to_world(np.column_stack((ix.ravel(), iy.ravel())))
    d = np.hypot(centres[:, 0] - x, centres[:, 1] - y).reshape(info.height, info.width) - radius
    out = grid.costs.copy()
    band = (d > inscribed) & (d <= inflation)
    decay = (costs.MAX_NON_OBSTACLE * np.exp(-3.0 * (d - inscribed))).astype(np.uint8)
    out[band] = np.maximum(out[band], decay[band])
    out[(d > 0) & (d <= inscribed)] = costs.INSCRIBED
    out[d <= 0] = costs.LETHAL
    return Grid(info, out)


def polyline(*corners: tuple[float, float], spacing: float = 0.05) -> Path:
    """A dense path through ``corners``, like a grid planner's (one point every ``spacing``)."""
    points = [np.array(corners[0], dtype=float)]
    for a, b in zip(corners[:-1], corners[1:], strict=True):
        a_, b_ = np.array(a, dtype=float), np.array(b, dtype=float)
        n = max(1, math.ceil(float(np.linalg.norm(b_ - a_)) / spacing))
        points.extend(a_ + (b_ - a_) * k / n for k in range(1, n + 1))
    return Path(np.array(points))


def step(pose: Pose2D, twist: Twist, dt: float = DT) -> Pose2D:
    """Exact unicycle motion on the arc ``twist`` for ``dt`` seconds."""
    v, w = twist.linear, twist.angular
    if abs(w) < 1e-12:
        return Pose2D(pose.x + v * dt * math.cos(pose.theta),
                      pose.y + v * dt * math.sin(pose.theta), pose.theta)
    theta = pose.theta + w * dt
    return Pose2D(pose.x + v / w * (math.sin(theta) - math.sin(pose.theta)),
                  pose.y - v / w * (math.cos(theta) - math.cos(pose.theta)), theta)


@dataclass
class Run:
    """What happened: the final true pose, every command and status, and the true poses."""

    pose: Pose2D
    commands: list[Twist] = field(default_factory=list)
    statuses: list[ControlStatus] = field(default_factory=list)
    poses: list[Pose2D] = field(default_factory=list)


def drive(controller: Controller, start: Pose2D, grid: Grid, *, seconds: float = 60.0,
          noise_xy: float = 0.0, noise_theta: float = 0.0,
          rng: np.random.Generator | None = None, until: ControlStatus = ControlStatus.ARRIVED
          ) -> Run:
    """Run the controller on the exact unicycle until it reports ``until`` or time runs out.

    ``noise_xy`` is the radial RMS [m] of white noise added to the position the controller sees
    (``noise_xy / sqrt(2)`` per axis); ``noise_theta`` the standard deviation [rad] on its heading.
    """
    rng = rng or np.random.default_rng(0)
    run = Run(start)
    pose, velocity = start, Twist()
    for _ in range(round(seconds / DT)):
        seen = pose
        if noise_xy or noise_theta:
            sx = noise_xy / math.sqrt(2.0)
            seen = Pose2D(pose.x + rng.normal(0.0, sx), pose.y + rng.normal(0.0, sx),
                          pose.theta + rng.normal(0.0, noise_theta))
        command = controller.compute(seen, velocity, grid, DT)
        run.commands.append(command.twist)
        run.statuses.append(command.status)
        run.poses.append(pose)
        if command.status is until:
            break
        pose = step(pose, command.twist)
        velocity = command.twist
    run.pose = pose
    return run
