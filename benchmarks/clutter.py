"""Clutter at speed: generated courses of obstacles, start and goal 10 m apart across each.

Issue 18's benchmark, with issue 31's second kind of course. Each course
(:mod:`polynav.worlds.clutter`) is a walled box with obstacles drawn from the seed, densities
stepping from sparse to barely passable over the courses, and a feasible way for the robot's
footprint guaranteed by construction and checked. ``--kind`` picks the kind: ``posts`` (thin
posts thrown at random, every gap a body width and more), ``lattice`` (posts packed into walls,
hooks and pockets, with gaps wider than the body but narrower than its diagonal), or ``all``
(both, ``--courses`` each, figures per kind). The full stack
drives the simulated robot from start to goal on simulated time; a goal not reached in 100 s of
simulated time is a timeout. Printed: success, collisions, timeouts, why goals failed, time
against the optimal path's time at top speed (the checked static path's length over the
controller's top speed; 1.0 never slows or turns), and the real-time factor. Issue 18's targets
are in ``targets`` and ``pass`` of the JSON line; the benchmark measures, it never fails on them.

With ``--robot`` the robot is a profile (a robot.yaml or a built-in name; default: the demo
robot), its footprint drawing the courses and its body, speeds and lidar in the simulator and the
stack. With ``--mapless`` the stack is given no map: it builds its rolling costmap from the
lidar and drives to the goal as a pose in the odometry frame (:mod:`polynav.nav.mapless`).

Run with ``polynav bench clutter [--kind {posts,lattice,all}] [--robot FILE] [--mapless]
[--courses N] [--only I [I ...]] [--seed S] [--json]``. ``--only`` drives only the given courses
of the ``--courses`` run (the same draw and density as in the whole run), to look at a failure
again: ``--kind lattice --courses 100 --only 41``.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

from polynav.errors import PolynavError
from polynav.nav.attempt import NavigationState
from polynav.robot.profile import RobotProfile, load_profile
from polynav.runtime.sim_driver import simulate, simulate_mapless
from polynav.worlds.clutter import KINDS, ClutterSpec, CourseError, draw

GOAL_TIME = 100.0  # [s of simulated time] per course
TARGET_SUCCESS_RATE = 0.98  # issue 31: each kind, profile and map mode
TARGET_TIME_RATIO = 2.5


def _commit() -> str | None:
    try:
        out = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=Path(__file__).resolve().parent,
            capture_output=True, text=True, check=True,
        )
    except (OSError, subprocess.CalledProcessError):
        return None
    return out.stdout.strip() or None


def density_of(course: int, courses: int) -> float:
    """Densities step evenly from 0 (sparse) to 1 (barely passable) over the courses."""
    return 0.0 if courses <= 1 else course / (courses - 1)


def run_course(
    index: int, courses: int, seed: int, profile: RobotProfile, *, mapless: bool,
    kind: str = "posts",
) -> dict[str, Any]:
    """Draw course ``index`` of ``kind`` for ``profile``'s body and drive it once; its figures.

    Course ``index`` of a kind is drawn from seed ``seed * 1000 + index``, so a failed course
    can be drawn again on its own (``draw(footprint, ClutterSpec(kind=..., density=...),
    seed * 1000 + index)``).
    """
    spec = ClutterSpec(kind=kind, density=density_of(index, courses))
    course = draw(profile.footprint, spec, seed * 1000 + index)
    top_speed = profile.cruise.linear_velocity
    run = simulate_mapless if mapless else simulate
    driver = run(course.world, seed=seed * 1000 + index, people=False, profile=profile)
    driver.run(0.5)  # the tracker settles on the first scans
    began = driver.now
    wall = time.perf_counter()
    driver.stack.go_to(driver.to_stack_frame(course.goal), driver.now)
    navigator = driver.stack.navigator
    while not navigator.state.finished and driver.now - began < GOAL_TIME:
        driver.step()
    wall_seconds = time.perf_counter() - wall
    sim_seconds = driver.now - began
    state = navigator.state
    attempt = navigator.attempt
    if state is NavigationState.SUCCEEDED:
        outcome = "reached"
    elif not state.finished:
        outcome = "timeout"
        navigator.cancel(driver.now)
    else:
        outcome = attempt.reason.value if attempt and attempt.reason else state.value
    optimal_time = course.optimal_length / top_speed
    return {
        "kind": kind,
        "course": index,
        "density": round(spec.density, 3),
        "posts": int(course.posts.shape[0]),
        "tight_gaps": sum(
            2.0 * profile.footprint.inscribed_radius < g.width
            < 2.0 * profile.footprint.circumscribed_radius for g in course.gaps
        ),
        "min_gap_m": round(course.min_gap, 3),
        "outcome": outcome,
        "collisions": len(driver.sim.collisions),
        "seconds": round(sim_seconds, 2),
        "optimal_seconds": round(optimal_time, 2),
        "time_ratio": round(sim_seconds / optimal_time, 3) if outcome == "reached" else None,
        "retries": attempt.retries if attempt else 0,
        "real_time_factor": round(sim_seconds / wall_seconds, 2) if wall_seconds > 0 else None,
    }


def overall_figures(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Success, collisions, timeouts and time ratio over every course, against the targets."""
    n = len(rows)
    reached = sum(r["outcome"] == "reached" for r in rows)
    ratios = [r["time_ratio"] for r in rows if r["time_ratio"] is not None]
    rtfs = [r["real_time_factor"] for r in rows if r["real_time_factor"] is not None]
    failures = Counter(r["outcome"] for r in rows if r["outcome"] != "reached")
    overall: dict[str, Any] = {
        "courses": n,
        "reached": reached,
        "success_rate": round(reached / n, 4) if n else 0.0,
        "collisions": sum(r["collisions"] for r in rows),
        "courses_with_collisions": sum(r["collisions"] > 0 for r in rows),
        "timeouts": failures.get("timeout", 0),
        "failures": dict(sorted(failures.items())),
        "time_ratio_mean": round(sum(ratios) / len(ratios), 3) if ratios else None,
        "time_ratio_max": max(ratios, default=None),
        "real_time_factor_min": min(rtfs, default=None),
        "real_time_factor_mean": round(sum(rtfs) / len(rtfs), 2) if rtfs else None,
    }
    checks = {
        "success_rate": n > 0 and overall["success_rate"] >= TARGET_SUCCESS_RATE,
        "collisions": overall["collisions"] == 0,
        "time_ratio": (overall["time_ratio_mean"] or math.inf) <= TARGET_TIME_RATIO,
    }
    overall["targets"] = {"success_rate": TARGET_SUCCESS_RATE, "collisions": 0,
                          "time_ratio_mean": TARGET_TIME_RATIO}
    overall["missed"] = [k for k, ok in checks.items() if not ok]
    overall["failed_courses"] = [{"course": r["course"], "outcome": r["outcome"]}
                                 for r in rows if r["outcome"] != "reached"]
    overall["pass"] = all(checks.values())
    return overall


def _fmt(value: float | None, spec: str) -> str:
    return "-" if value is None else format(value, spec)


def run_kind(kind: str, args: argparse.Namespace, profile: RobotProfile) -> list[dict[str, Any]]:
    """Drive ``args.courses`` courses of ``kind``, printing a line each; their rows."""
    print(f"kind {kind}:")
    print(f"{'course':>6s}{'density':>9s}{'posts':>7s}{'gap':>7s}  {'outcome':14s}"
          f"{'coll.':>6s}{'time':>8s}{'optimal':>9s}{'ratio':>7s}{'retries':>8s}{'RTF':>7s}")
    rows: list[dict[str, Any]] = []
    for index in args.only if args.only else range(args.courses):
        try:
            row = run_course(index, args.courses, args.seed, profile, mapless=args.mapless,
                             kind=kind)
        except CourseError as exc:
            print(f"{index:>6d} skipped: {exc}", flush=True)
            continue
        rows.append(row)
        print(f"{row['course']:>6d}{row['density']:>9.2f}{row['posts']:>7d}"
              f"{row['min_gap_m']:>7.2f}  {row['outcome']:14s}{row['collisions']:>6d}"
              f"{row['seconds']:>8.1f}{row['optimal_seconds']:>9.1f}"
              f"{_fmt(row['time_ratio'], '.2f'):>7s}{row['retries']:>8d}"
              f"{_fmt(row['real_time_factor'], '.1f'):>7s}", flush=True)
    return rows


def _print_overall(kind: str, overall: dict[str, Any]) -> None:
    print(f"overall {kind}: {overall['reached']}/{overall['courses']} reached "
          f"({100.0 * overall['success_rate']:.1f} %), {overall['collisions']} collisions, "
          f"{overall['timeouts']} timeouts, time vs optimal mean "
          f"{_fmt(overall['time_ratio_mean'], '.2f')} (max {_fmt(overall['time_ratio_max'], '.2f')}"
          f"), real-time factor min {_fmt(overall['real_time_factor_min'], '.1f')}")
    failed = [f"{r['course']} {r['outcome']}" for r in overall.get("failed_courses", [])]
    if failed:
        print(f"  failed courses: {', '.join(failed)}")
    print(f"  targets {'met' if overall['pass'] else 'missed: ' + ', '.join(overall['missed'])}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="polynav bench clutter",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--kind", choices=[*KINDS, "all"], default="all",
                        help="course kind, or all of them (default %(default)s)")
    parser.add_argument("--courses", type=int, default=100,
                        help="courses per kind, sparse to barely passable (default %(default)s)")
    parser.add_argument("--only", type=int, nargs="+", default=None, metavar="I",
                        help="drive only these courses of the --courses run (same draw)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--robot", default=None,
                        help="robot profile: a robot.yaml or a built-in name (default: demo)")
    parser.add_argument("--mapless", action="store_true",
                        help="navigate with no prior map (rolling costmap from the lidar)")
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    args = parser.parse_args(argv)
    if args.courses < 1:
        print("polynav bench clutter: --courses must be >= 1", file=sys.stderr)
        return 2
    if args.only and not all(0 <= i < args.courses for i in args.only):
        print("polynav bench clutter: --only takes course numbers below --courses",
              file=sys.stderr)
        return 2
    try:
        profile = load_profile(args.robot)
    except PolynavError as exc:
        print(f"polynav bench clutter: {exc}", file=sys.stderr)
        return 2
    kinds = list(KINDS) if args.kind == "all" else [args.kind]
    print(f"polynav bench clutter: {', '.join(kinds)}, {args.courses} courses each, seed "
          f"{args.seed}, robot {profile.name} ({profile.footprint!r}), top speed "
          f"{profile.cruise.linear_velocity:g} m/s, {'no map' if args.mapless else 'with the map'}"
          f", Python {platform.python_version()}")
    rows: list[dict[str, Any]] = []
    figures: dict[str, dict[str, Any]] = {}
    for kind in kinds:
        kind_rows = run_kind(kind, args, profile)
        rows += kind_rows
        figures[kind] = overall_figures(kind_rows)
    for kind in kinds:
        _print_overall(kind, figures[kind])
    if args.json:
        print(json.dumps({
            "seed": args.seed, "courses": args.courses, "kinds": kinds, "robot": profile.name,
            "footprint": repr(profile.footprint), "mapless": args.mapless,
            "top_speed": profile.cruise.linear_velocity, "overall": figures, "rows": rows,
            "commit": _commit(), "machine": platform.platform(),
        }))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
