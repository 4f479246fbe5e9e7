"""Record a CARMEN log, with exact ground truth, by driving the simulator along waypoints.

The public logs have no ground truth of their own (Intel's relations are hand-made from a
subset of scans), and they may not ship with polynav. The simulator knows the true pose at every
instant, so a log recorded from it scores a SLAM run exactly: :func:`record` drives
:class:`~polynav.robot.sim.simulation.Simulation` through a list of waypoints, steering on the
*true* pose (a chauffeur, not a navigator), and keeps every ``scan_every``-th scan as a
``RAWLASER1`` line and the wheel odometry as ``ODOM`` lines, with the true pose of each kept
scan beside it.

:func:`relations_from_truth` turns that ground truth into relations in the Freiburg format for
:mod:`polynav.mapping.evaluation`: every consecutive pair, and every pair that revisits a place
after a long time (what only a closed loop gets right).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from polynav.geometry import Pose2D, Twist, angle_diff
from polynav.robot.sim.simulation import Simulation
from polynav.worlds.world import World

# Loop on demo floor 1: out of the lobby, east along the corridor and back, then round the
# lobby's west and south sides (each leg keeps 0.5 m or more from the walls).
DEMO_LOOP = (
    (8.0, 8.5), (8.5, 12.0), (28.0, 12.0), (8.5, 11.8), (1.2, 11.5), (1.2, 4.5), (8.5, 4.5),
    (8.5, 8.5),
)


@dataclass(frozen=True, slots=True)
class Recording:
    """A recorded log and its ground truth.

    Attributes:
        lines: the CARMEN log's lines (no newlines).
        truth: per kept scan, its timestamp exactly as in the log and the true pose.
        odometry_origin: the world pose where the log's odometry frame starts (the ``ODOM``
            poses count from zero there, as a real base's do), so that a map made from the log
            can be laid over the world.
    """

    lines: tuple[str, ...]
    truth: tuple[tuple[str, Pose2D], ...]
    odometry_origin: Pose2D = Pose2D()

    def write(self, log_path: str | Path, truth_path: str | Path) -> None:
        """Write the log and the ground truth (``timestamp x y theta`` per scan)."""
        Path(log_path).write_text("\n".join(self.lines) + "\n", encoding="utf-8")
        Path(truth_path).write_text(
            "".join(f"{t} {p.x:.6f} {p.y:.6f} {p.theta:.6f}\n" for t, p in self.truth),
            encoding="utf-8")


def record(
    world: World,
    waypoints: Sequence[tuple[float, float]] = DEMO_LOOP,
    *,
    seed: int = 0,
    floor: str | None = None,
    speed: float = 0.6,
    scan_every: int = 3,
    odom_rate: float = 10.0,
    time_limit: float = 600.0,
) -> Recording:
    """Drive the simulated robot through ``waypoints`` and record its log.

    Args:
        world: the simulated world.
        waypoints: (x, y) [m] to visit in order; the robot starts on the first, facing the
            second.
        seed: seeds the simulator's noise.
        floor: the floor (default: the world's start floor).
        speed: cruising speed [m/s].
        scan_every: keep one scan in this many (the lidar runs at 15 Hz).
        odom_rate: ``ODOM`` lines per second [Hz].
        time_limit: stop after this much simulated time [s] even if not arrived.

    Returns:
        The log lines and ground truth.
    """
    x0, y0 = waypoints[0]
    x1, y1 = waypoints[1]
    sim = Simulation(world, seed=seed, floor=floor, pose=Pose2D(x0, y0, math.atan2(y1 - y0,
                                                                                 x1 - x0)),
                     people=False)
    # A scripted drive has no door rule (the runtime opens doors on a route): the building's
    # doors and gates stand open, as a log recorded in the day would see them.
    for door in sim.scene.doors.values():
        door.open("recording")
    lines: list[str] = ["# polynav simulator recording", "PARAM robot_frontlaser_offset 0.0"]
    truth: list[tuple[str, Pose2D]] = []
    target = 1
    last_scan = -1.0
    scans = 0
    next_odom = 0.0
    while target < len(waypoints) and sim.clock.now() < time_limit:
        pose = sim.true_pose
        tx, ty = waypoints[target]
        distance = math.hypot(tx - pose.x, ty - pose.y)
        if distance < 0.15:
            target += 1
            continue
        error = angle_diff(math.atan2(ty - pose.y, tx - pose.x), pose.theta)
        if abs(error) > 0.3:
            sim.drive(Twist(0.0, max(-1.0, min(1.0, 1.5 * error))))
        else:
            sim.drive(Twist(min(speed, distance), 2.0 * error))
        sim.step()
        now = sim.clock.now()
        odom = sim.odometry
        if now >= next_odom:
            lines.append(_odom_line(odom.pose, now))
            next_odom = now + 1.0 / odom_rate
        scan = sim.scan
        if scan is not None and scan.stamp > last_scan:
            last_scan = scan.stamp
            scans += 1
            if scans % scan_every == 0:
                stamp = f"{scan.stamp:.6f}"
                lines.append(_odom_line(odom.pose, now))
                ranges = np.where(np.isfinite(scan.ranges), scan.ranges, scan.range_max)
                fov = scan.angle_increment * scan.ranges.shape[0]
                lines.append(
                    f"RAWLASER1 0 {scan.angle_min:.6f} {fov:.6f} {scan.angle_increment:.6f} "
                    f"{scan.range_max:.3f} 0.01 0 {ranges.shape[0]} "
                    + " ".join(f"{r:.3f}" for r in ranges)
                    + f" 0 {stamp} polynav {stamp}")
                truth.append((stamp, sim.true_pose))
    return Recording(tuple(lines), tuple(truth), sim.odometry_origin)


def _odom_line(pose: Pose2D, now: float) -> str:
    return (f"ODOM {pose.x:.6f} {pose.y:.6f} {pose.theta:.6f} 0 0 0 {now:.6f} polynav "
            f"{now:.6f}")


def relations_from_truth(
    truth: Sequence[tuple[str, Pose2D]], *, revisit_distance: float = 1.0,
    revisit_gap: int = 100, stride: int = 5,
) -> list[str]:
    """Freiburg relation lines (``t1 t2 x y 0 0 0 yaw``) from a ground truth.

    Args:
        truth: (timestamp, true pose) per scan.
        revisit_distance: pairs of scans this close [m] ...
        revisit_gap: ... and at least this many scans apart are loop relations.
        stride: loop relations are taken from every ``stride``-th scan.
    """
    out = []

    def line(a: int, b: int) -> str:
        d = truth[b][1].relative_to(truth[a][1])
        return f"{truth[a][0]} {truth[b][0]} {d.x:.6f} {d.y:.6f} 0 0 0 {d.theta:.6f}"

    for k in range(len(truth) - 1):
        out.append(line(k, k + 1))
    for a in range(0, len(truth), stride):
        for b in range(a + revisit_gap, len(truth), stride):
            if truth[a][1].distance_to(truth[b][1]) <= revisit_distance:
                out.append(line(a, b))
    return out
