"""Navigation on floor plans polynav was never tuned on: every MovingAI map up to 256 x 256 cells.

Each map becomes a world (``polynav world from-map``: 1 m per cell, 0.05 m per pixel, goal points
and walkers from a seed); the full stack drives the simulated robot through the goals in turn on
simulated time. Printed per map and overall: goals reached, path efficiency (the time per goal
against the shortest path on the static map at the controller's top speed; 1.0 is a robot that
never slows, turns or waits), collisions, the closest approach to a person (centre to centre,
ground truth), the real-time factor, and why goals failed; the JSON line also lists every goal's
outcome.

Two closest approaches are measured. ``closest_person_m`` is over every instant, whoever moved:
the simulated walkers do not steer round the robot, so one may walk past a robot that stands
still. ``closest_person_approached_m`` counts only the instants when the robot itself was closing
in on that person (the gap shrinking, and the robot's own velocity towards them above
``APPROACH_SPEED``): the distance the robot chose, which is what the social-distance target
judges.

The real-time factor is simulated seconds per second of this process's CPU time
(``time.process_time``): on a shared, loaded machine wall time measures the neighbours; the
wall-clock figure is in the JSON line too (``real_time_factor_wall``).

The figures are checked against issue 10's targets (``targets`` and ``pass`` in the JSON line);
the benchmark measures, it never fails on them.

A goal may take ``60 s + 3 x`` its shortest path at top speed before it counts as failed
("timeout"), so a long maze corridor is not a failure by itself.

Run with ``polynav bench nav [--maps DIR] [--limit N] [--max-cells N] [--goals N] [--walkers N]
[--seed N] [--json]``.
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
from polynav.localization.interface import LocalizationState
from polynav.maps import movingai
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.nav.attempt import NavigationState
from polynav.nav.stack import StackConfig, stack_config_for
from polynav.planning.grid_planner import GridPlanner
from polynav.robot.profile import RobotProfile, load_profile
from polynav.runtime.sim_driver import SimDriver, simulate
from polynav.worlds.from_map import FromMapOptions, load_plan, plan_world, to_world

DATA = Path(__file__).resolve().parent.parent / "data" / "movingai"
MAX_CELLS = 256
GOAL_TIME_BASE = 60.0  # [s of simulated time] a goal may take beyond ...
GOAL_TIME_FACTOR = 3.0  # ... this many times its shortest path at top speed
UNPLANNED_GOAL_TIME = 600.0  # [s] when the shortest path itself cannot be found
# Issue 10's targets for bench nav.
TARGET_SUCCESS_RATE = 0.99
TARGET_PATH_EFFICIENCY = 1.3
TARGET_REAL_TIME_FACTOR = 20.0
APPROACH_SPEED = 0.02  # [m/s] the robot's own speed towards a person that counts as approaching


def _commit() -> str | None:
    try:
        out = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=Path(__file__).resolve().parent,
            capture_output=True, text=True, check=True,
        )
    except (OSError, subprocess.CalledProcessError):
        return None
    return out.stdout.strip() or None


def find_maps(folder: Path, max_cells: int = MAX_CELLS) -> tuple[list[Path], list[str]]:
    """The readable ``.map`` files of ``folder`` of at most ``max_cells`` a side, sorted by name;
    and a note for each one left out."""
    found: list[Path] = []
    left_out: list[str] = []
    for path in sorted(folder.glob("*.map")):
        try:
            height, width = movingai.load_grid(path).shape
        except PolynavError as exc:
            left_out.append(f"{path.name}: {exc}")
            continue
        if height <= max_cells and width <= max_cells:
            found.append(path)
        else:
            left_out.append(f"{path.name}: {width} x {height} cells, more than {max_cells}")
    return found, left_out


def _percentile(values: list[float], q: float) -> float | None:
    if not values:
        return None
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


class _Leg:
    """What happened while driving to one goal. (Not a dataclass: ``polynav bench`` loads this
    file without registering it in ``sys.modules``, which dataclasses need.)"""

    def __init__(self) -> None:
        self.wall_seconds = 0.0
        self.cpu_seconds = 0.0
        self.closest_person = math.inf  # [m], centre to centre; inf with no one about
        self.closest_approached = math.inf  # [m], the same while the robot closed in
        self.localization_error_max = 0.0  # [m], estimate against ground truth
        self.lost = False  # localization declared LOST at some moment


def _drive(driver: SimDriver, timeout: float) -> _Leg:
    """Step until the attempt finishes or ``timeout`` simulated seconds pass."""
    leg = _Leg()
    end = driver.now + timeout
    wall = time.perf_counter()
    cpu = time.process_time()
    last_gaps: list[float] = []
    while not driver.stack.navigator.state.finished and driver.now < end:
        driver.step()
        true = driver.sim.true_pose
        speed = driver.sim.true_twist.linear
        c, s = math.cos(true.theta), math.sin(true.theta)
        gaps = []
        for k, person in enumerate(driver.sim.people_poses()):
            dx, dy = person.x - true.x, person.y - true.y
            d = math.hypot(dx, dy)
            gaps.append(d)
            leg.closest_person = min(leg.closest_person, d)
            closing = k < len(last_gaps) and d < last_gaps[k]
            if closing and d > 0.0 and speed * (dx * c + dy * s) / d > APPROACH_SPEED:
                leg.closest_approached = min(leg.closest_approached, d)
        last_gaps = gaps
        estimate = driver.stack.estimate
        leg.localization_error_max = max(
            leg.localization_error_max,
            math.hypot(estimate.pose.x - true.x, estimate.pose.y - true.y),
        )
        leg.lost |= estimate.state is LocalizationState.LOST
    leg.wall_seconds = time.perf_counter() - wall
    leg.cpu_seconds = time.process_time() - cpu
    return leg


def run_map(path: Path, goals: int, walkers: int, seed: int,
            profile: RobotProfile | None = None) -> dict[str, Any]:
    """Drive one world's goals in turn with ``profile``'s robot (default: the demo robot); its
    figures.

    Raises:
        PolynavError: the map does not make a world (no room for the robot, or for two points).
    """
    profile = profile or load_profile()
    options = FromMapOptions(points=goals, walkers=walkers, seed=seed,
                             robot_radius=profile.circumscribed_radius)
    planned = plan_world(path.stem, load_plan(path, options), options, allow_fewer=True)
    world = to_world(planned, options)
    floor = world.floors[0]
    stack = stack_config_for(profile)
    top_speed = stack.controller.max_linear_velocity
    static = Costmap.from_map(floor.map, CostmapConfig(obstacle_layer=False))
    planner = GridPlanner(stack.planner)
    driver = simulate(world, seed=seed, people=walkers > 0, stack_config=stack,
                      sim_config=profile.sim_config())
    driver.run(1.0)  # warm the kernels and the tracker: start-up is not the steady state
    reached = 0
    efficiencies: list[float] = []
    failures: Counter[str] = Counter()
    closest = approached = math.inf
    sim_seconds = wall_seconds = cpu_seconds = error_max = worst_final = 0.0
    outcomes: list[dict[str, Any]] = []
    lost = 0
    for point in floor.points[1:]:
        try:
            optimal = planner.plan(static, driver.sim.true_pose, point.pose).length
            timeout = GOAL_TIME_BASE + GOAL_TIME_FACTOR * optimal / top_speed
        except PolynavError:
            optimal, timeout = math.nan, UNPLANNED_GOAL_TIME
        began = driver.now
        driver.stack.go_to(point.pose, driver.now)
        leg = _drive(driver, timeout)
        wall_seconds += leg.wall_seconds
        cpu_seconds += leg.cpu_seconds
        sim_seconds += driver.now - began
        closest = min(closest, leg.closest_person)
        approached = min(approached, leg.closest_approached)
        error_max = max(error_max, leg.localization_error_max)
        lost += leg.lost
        state = driver.stack.navigator.state
        outcome = "reached"
        final = driver.sim.true_pose.distance_to(point.pose)  # true pose against the goal
        if state is NavigationState.SUCCEEDED:
            reached += 1
            worst_final = max(worst_final, final)
            if optimal > 0.5:  # shorter, turning on the spot is most of the time
                efficiencies.append((driver.now - began) / (optimal / top_speed))
        else:
            attempt = driver.stack.navigator.attempt
            reason = attempt.reason.value if attempt and attempt.reason else None
            outcome = reason or ("timeout" if not state.finished else state.value)
            failures[outcome] += 1
            if not state.finished:
                driver.stack.navigator.cancel(driver.now)
        outcomes.append({
            "goal": point.name, "outcome": outcome, "seconds": round(driver.now - began, 1),
            "optimal_m": None if math.isnan(optimal) else round(optimal, 2),
            "final_error_m": round(final, 3),
            "closest_person_m": _finite(leg.closest_person),
            "closest_person_approached_m": _finite(leg.closest_approached),
            "lost": leg.lost,
        })
    count = len(floor.points) - 1
    return {
        "map": path.name,
        "goals": count,
        "reached": reached,
        "success_rate": round(reached / count, 4),
        "worst_final_error_m": round(worst_final, 3),
        "path_efficiency_median": _rounded(_percentile(efficiencies, 0.5)),
        "path_efficiency_p90": _rounded(_percentile(efficiencies, 0.9)),
        "path_efficiencies": [round(e, 3) for e in efficiencies],
        "failures": dict(sorted(failures.items())),
        "collisions": len(driver.sim.collisions),
        "walkers": len(floor.people),
        "closest_person_m": _finite(closest),
        "closest_person_approached_m": _finite(approached),
        "goals_with_localization_lost": lost,
        "localization_error_max_m": round(error_max, 3),
        "sim_seconds": round(sim_seconds, 1),
        "real_time_factor": round(sim_seconds / cpu_seconds, 2) if cpu_seconds > 0 else None,
        "real_time_factor_wall": (
            round(sim_seconds / wall_seconds, 2) if wall_seconds > 0 else None
        ),
        "outcomes": outcomes,
    }


def _finite(value: float) -> float | None:
    return None if math.isinf(value) else round(value, 3)


def _rounded(value: float | None) -> float | None:
    return None if value is None else round(value, 3)


def overall_figures(rows: list[dict[str, Any]], social_distance: float) -> dict[str, Any]:
    """The figures over every map, and whether they meet issue 10's targets."""
    goals = sum(r["goals"] for r in rows)
    reached = sum(r["reached"] for r in rows)
    effs = [e for r in rows for e in r["path_efficiencies"]]
    closests = [r["closest_person_m"] for r in rows if r["closest_person_m"] is not None]
    approached = [r["closest_person_approached_m"] for r in rows
                  if r.get("closest_person_approached_m") is not None]
    rtfs = [r["real_time_factor"] for r in rows if r["real_time_factor"] is not None]
    failures: Counter[str] = Counter()
    for r in rows:
        failures.update(r["failures"])
    sim_seconds = sum(r["sim_seconds"] for r in rows)
    overall: dict[str, Any] = {
        "maps": len(rows),
        "goals": goals,
        "reached": reached,
        "success_rate": round(reached / goals, 4) if goals else 0.0,
        "worst_final_error_m": max((r["worst_final_error_m"] for r in rows), default=0.0),
        # Over every goal reached on every map: a map of three goals weighs less than one of 20.
        "path_efficiency_median": _percentile(effs, 0.5),
        "path_efficiency_p90": _percentile(effs, 0.9),
        "failures": dict(sorted(failures.items())),
        "collisions": sum(r["collisions"] for r in rows),
        "closest_person_m": min(closests, default=None),
        "closest_person_approached_m": min(approached, default=None),
        "goals_with_localization_lost": sum(r["goals_with_localization_lost"] for r in rows),
        "real_time_factor_min": min(rtfs, default=None),
        "sim_seconds": round(sim_seconds, 1),
    }
    checks = {
        "success_rate": goals > 0 and overall["success_rate"] >= TARGET_SUCCESS_RATE,
        "collisions": overall["collisions"] == 0,
        "path_efficiency": (overall["path_efficiency_median"] or math.inf)
        <= TARGET_PATH_EFFICIENCY,
        "closest_person": not approached or min(approached) >= social_distance,
        "real_time_factor": bool(rtfs) and min(rtfs) >= TARGET_REAL_TIME_FACTOR,
    }
    overall["targets"] = {
        "success_rate": TARGET_SUCCESS_RATE, "collisions": 0,
        "path_efficiency": TARGET_PATH_EFFICIENCY,
        "closest_person_approached_m": social_distance,
        "real_time_factor": TARGET_REAL_TIME_FACTOR,
    }
    overall["missed"] = [name for name, ok in checks.items() if not ok]
    overall["pass"] = all(checks.values())
    return overall


def _fmt(value: float | None, spec: str) -> str:
    return "-" if value is None else format(value, spec)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="polynav bench nav", description=__doc__.splitlines()[0])
    parser.add_argument("--maps", type=Path, default=DATA, help="folder of MovingAI .map files")
    parser.add_argument("--limit", type=int, default=None, help="only the first N maps")
    parser.add_argument("--max-cells", type=int, default=MAX_CELLS,
                        help="leave out maps larger than this a side (default %(default)s)")
    parser.add_argument("--goals", type=int, default=20)
    parser.add_argument("--walkers", type=int, default=3)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    parser.add_argument("--robot", default=None,
                        help="robot profile: a robot.yaml or a built-in name (default: demo)")
    args = parser.parse_args(argv)
    try:
        profile = load_profile(args.robot)
    except PolynavError as exc:
        print(f"polynav bench nav: {exc}", file=sys.stderr)
        return 2
    maps, left_out = find_maps(args.maps, args.max_cells) if args.maps.is_dir() else ([], [])
    if args.limit is not None:
        maps = maps[: args.limit]
    if not maps:
        print(f"polynav bench nav: no MovingAI maps (.map) of at most {args.max_cells} x "
              f"{args.max_cells} cells in {args.maps} (data/movingai/ in the repository has "
              "them)", file=sys.stderr)
        return 2
    print(f"polynav bench nav: {len(maps)} maps at 1 m per cell, {args.goals} goals and "
          f"{args.walkers} walkers each, seed {args.seed}, Python {platform.python_version()}")
    for note in left_out:
        print(f"  left out {note}")
    print(f"{'map':28s}{'reached':>10s}{'worst':>7s}{'eff.med':>9s}{'eff.p90':>9s}{'coll.':>7s}"
          f"{'walkers':>8s}{'closest':>9s}{'appr.':>7s}{'loc.err':>8s}{'lost':>5s}{'RTF':>7s}"
          "  failures")
    rows: list[dict[str, Any]] = []
    skipped: list[str] = []
    for path in maps:
        try:
            row = run_map(path, args.goals, args.walkers, args.seed, profile)
        except PolynavError as exc:
            skipped.append(f"{path.name}: {exc}")
            print(f"{path.name:28s} skipped: {exc}", flush=True)
            continue
        rows.append(row)
        failures = ", ".join(f"{k} {v}" for k, v in row["failures"].items())
        print(f"{row['map']:28s}{row['reached']:>5d}/{row['goals']:<4d}"
              f"{row['worst_final_error_m']:>7.3f}"
              f"{_fmt(row['path_efficiency_median'], '.2f'):>9s}"
              f"{_fmt(row['path_efficiency_p90'], '.2f'):>9s}{row['collisions']:>7d}"
              f"{row['walkers']:>8d}{_fmt(row['closest_person_m'], '.2f'):>9s}"
              f"{_fmt(row['closest_person_approached_m'], '.2f'):>7s}"
              f"{row['localization_error_max_m']:>8.2f}{row['goals_with_localization_lost']:>5d}"
              f"{_fmt(row['real_time_factor'], '.1f'):>7s}"
              f"  {failures}", flush=True)
    overall = overall_figures(rows, StackConfig().people.social_distance)
    print(f"overall: {overall['reached']}/{overall['goals']} goals "
          f"({100.0 * overall['success_rate']:.1f} %, worst final error "
          f"{100.0 * overall['worst_final_error_m']:.1f} cm) on {overall['maps']} maps, "
          f"path efficiency "
          f"median {_fmt(overall['path_efficiency_median'], '.2f')} (p90 "
          f"{_fmt(overall['path_efficiency_p90'], '.2f')}), {overall['collisions']} collisions, "
          f"closest approach to a person {_fmt(overall['closest_person_m'], '.2f')} m (by the "
          f"robot: {_fmt(overall['closest_person_approached_m'], '.2f')} m), slowest "
          f"real-time factor {_fmt(overall['real_time_factor_min'], '.1f')}")
    print(f"targets {'met' if overall['pass'] else 'missed: ' + ', '.join(overall['missed'])}")
    if args.json:
        print(json.dumps({
            "seed": args.seed, "robot": profile.name, "goals_per_map": args.goals,
            "walkers_per_map": args.walkers,
            "maps": rows, "skipped": skipped, "left_out": left_out, "overall": overall,
            "commit": _commit(), "machine": platform.platform(),
        }))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
