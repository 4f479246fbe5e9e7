"""Full-stack simulation benchmark: the demo site's named points as a fixed list of goals.

Drives simulated sensors, localization, costmap, planner and controller on simulated time and
reports how fast that runs against real time (DESIGN §8: >= 20x for one robot on one core), how
many goals were reached and the worst final error among them (true pose against the goal, at
arrival), the mean localization error against ground truth, and collisions.

The localization error is sampled at each control tick, against the true pose at the estimate's
own stamp: between ticks the estimate stands still while the robot moves on, and comparing it
with the truth of a later physics step measured the tick's age (half a 20 Hz period at 2 m/s is
5 cm), not localization.

Walkers walk unless ``--no-people``. Run with ``polynav bench sim [--json] [--seed N] [--seeds N]
[--world DIR] [--floors NAME ...] [--no-people]``.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from polynav.errors import PolynavError
from polynav.nav.attempt import GoalOptions, NavigationState
from polynav.robot.profile import RobotProfile, load_profile
from polynav.runtime.goal_commands import UNDOCK_DISTANCE
from polynav.runtime.sim_driver import simulate
from polynav.site import PointKind
from polynav.worlds import load_world

BUDGET_REAL_TIME_FACTOR = 20.0


def _commit() -> str | None:
    try:
        out = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            cwd=Path(__file__).resolve().parent,
            capture_output=True,
            text=True,
            check=True,
        )
    except (OSError, subprocess.CalledProcessError):
        return None
    return out.stdout.strip() or None


def run_seed(world_name: str, floors: list[str] | None, seed: int, people: bool,
             timeout: float, profile: RobotProfile | None = None) -> dict[str, Any]:
    """Every named point of every floor, in turn, with one seed; its figures (the robot of
    ``profile``, else of the world's ``robot:`` entry, else the demo robot)."""
    world = load_world(world_name)
    goals = succeeded = collisions = 0
    worst_final = 0.0
    error_sum = 0.0
    error_samples = 0
    sim_seconds = wall_seconds = 0.0
    failed: list[str] = []
    for floor_name in floors or [f.name for f in world.floors]:
        floor = world.floor(floor_name)
        start = next(
            (p.pose for p in floor.points if p.kind.value == "initial"), floor.points[0].pose
        )
        driver = simulate(world, seed=seed, floor=floor_name, pose=start, people=people,
                          profile=profile)
        # The bare stack has no door rule (the runtime opens doors on the way, measured by
        # bench fleet): the building's doors are held open, as they were walls-free before.
        for door in driver.sim.scene.doors.values():
            door.open("bench")
        # Warm the kernels and the tracker before timing: start-up is not the steady state.
        driver.run(max([1.0, *(d.spec.open_time for d in driver.sim.scene.doors.values())]))
        sim_start, wall_start = driver.now, time.perf_counter()
        docked = False
        for point in floor.points:
            goals += 1
            # As the runtime does: a charger point is reached by docking (its pose touches the
            # plate), and the next goal first backs off the charger.
            options = GoalOptions(
                dock=point.kind is PointKind.CHARGER,
                undock_distance=UNDOCK_DISTANCE if docked else None,
            )
            driver.stack.go_to(point.pose, driver.now, options)
            end = driver.now + timeout
            while not driver.stack.navigator.state.finished and driver.now < end:
                stamp, true = driver.now, driver.sim.true_pose
                driver.step()
                estimate = driver.stack.estimate
                if estimate.stamp == stamp:  # a control tick localized at this instant
                    est = estimate.pose
                    error_sum += math.hypot(est.x - true.x, est.y - true.y)
                    error_samples += 1
            ok = driver.stack.navigator.state is NavigationState.SUCCEEDED
            docked = ok and point.kind is PointKind.CHARGER
            final = driver.sim.true_pose.distance_to(point.pose)
            succeeded += ok
            if ok:
                worst_final = max(worst_final, final)
            attempt = driver.stack.navigator.attempt
            reason = attempt.reason.value if attempt and attempt.reason else ""
            if not ok:
                failed.append(f"{floor_name}/{point.name} ({reason or 'timeout'})")
            uncertainty = attempt.arrival_uncertainty if attempt else None
            sd = f" sd={uncertainty.position:.3f}m" if uncertainty is not None else ""
            print(f"{floor_name:>8} {point.name:<18} {'ok' if ok else 'FAILED ' + reason:<24} "
                  f"t={driver.now:7.1f}s err={final:.3f}m{sd}")
        sim_seconds += driver.now - sim_start
        wall_seconds += time.perf_counter() - wall_start
        collisions += len(driver.sim.collisions)
    return {
        "seed": seed,
        "goals": goals,
        "succeeded": succeeded,
        "worst_final_error_m": worst_final,
        "failed": failed,
        "collisions": collisions,
        "real_time_factor": sim_seconds / wall_seconds if wall_seconds > 0 else math.inf,
        "mean_localization_error_m": error_sum / error_samples if error_samples else 0.0,
        "sim_seconds": sim_seconds,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="polynav bench sim", description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    parser.add_argument("--seed", type=int, default=0, help="the first seed")
    parser.add_argument("--seeds", type=int, default=1, help="how many seeds, from --seed on")
    parser.add_argument("--world", default="demo")
    parser.add_argument("--floors", nargs="*", help="floor names (default: all)")
    parser.add_argument("--no-people", action="store_true", help="keep the walkers still")
    parser.add_argument("--timeout", type=float, default=180.0, help="sim seconds per goal")
    parser.add_argument("--robot", default=None,
                        help="robot profile: a robot.yaml or a built-in name (default: the "
                             "world's, else demo)")
    args = parser.parse_args(argv)
    if args.seeds < 1:
        parser.error("--seeds must be >= 1")
    try:
        profile = load_profile(args.robot) if args.robot is not None else None
    except PolynavError as exc:
        print(f"polynav bench sim: {exc}", file=sys.stderr)
        return 2

    runs = []
    for seed in range(args.seed, args.seed + args.seeds):
        print(f"-- seed {seed}{'' if args.no_people else ', walkers on'}")
        run = run_seed(args.world, args.floors, seed, not args.no_people, args.timeout, profile)
        runs.append(run)
        print(f"seed {seed}: goals {run['goals']}, succeeded {run['succeeded']} "
              f"(worst final error {run['worst_final_error_m'] * 100:.1f} cm), "
              f"collisions {run['collisions']}, "
              f"real-time factor {run['real_time_factor']:.1f}x")
    goals = sum(r["goals"] for r in runs)
    succeeded = sum(r["succeeded"] for r in runs)
    collisions = sum(r["collisions"] for r in runs)
    sim_seconds = sum(r["sim_seconds"] for r in runs)
    rtf = min(r["real_time_factor"] for r in runs)
    worst_final = max(r["worst_final_error_m"] for r in runs)
    mean_error = sum(r["mean_localization_error_m"] for r in runs) / len(runs)
    print(f"goals {goals}, succeeded {succeeded} (worst final error {worst_final * 100:.1f} cm), "
          f"collisions {collisions}")
    print(f"simulated {sim_seconds:.1f} s; slowest real-time factor {rtf:.1f}x "
          f"(budget {BUDGET_REAL_TIME_FACTOR:.0f}x)")
    print(f"mean localization error {mean_error * 100:.1f} cm")
    if args.json:
        print(json.dumps({
            "world": args.world,
            "robot": profile.name if profile is not None else None,
            "people": not args.no_people,
            "seeds": [r["seed"] for r in runs],
            "goals": goals,
            "succeeded": succeeded,
            "success_rate": round(succeeded / goals, 4) if goals else 0.0,
            "worst_final_error_m": round(worst_final, 4),
            "failed": [f"seed {r['seed']}: {f}" for r in runs for f in r["failed"]],
            "collisions": collisions,
            "real_time_factor": round(rtf, 2),
            "mean_localization_error_m": round(mean_error, 4),
            "sim_seconds": round(sim_seconds, 1),
            "budget_real_time_factor": BUDGET_REAL_TIME_FACTOR,
            "pass": rtf >= BUDGET_REAL_TIME_FACTOR and succeeded == goals and collisions == 0,
            "commit": _commit(),
            "machine": platform.platform(),
        }))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
