"""Navigation on floor plans polynav was never tuned on: every MovingAI map up to 256 x 256 cells.

Each map becomes a world (``polynav world from-map``: 1 m per cell, 0.05 m per pixel, goal points
and walkers from a seed); the full stack drives the simulated robot through the goals in turn on
simulated time. Printed per map and overall: goals reached, path efficiency (the time per goal
against the shortest path on the static map at the controller's top speed; 1.0 is a robot that
never slows, turns or waits), collisions, the closest approach to a person (centre to centre),
and the real-time factor.

Run with ``polynav bench nav [--maps DIR] [--limit N] [--goals N] [--walkers N] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import sys
import time
from pathlib import Path
from typing import Any

from polynav.errors import PolynavError
from polynav.maps import movingai
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.nav.attempt import NavigationState
from polynav.nav.stack import StackConfig
from polynav.planning.grid_planner import GridPlanner
from polynav.runtime.sim_driver import simulate
from polynav.worlds.from_map import FromMapOptions, load_plan, plan_world, to_world

DATA = Path(__file__).resolve().parent.parent / "data" / "movingai"
MAX_CELLS = 256
TIMEOUT = 300.0  # [s of simulated time] per goal


def _maps(folder: Path) -> list[Path]:
    found = []
    for path in sorted(folder.glob("*.map")):
        try:
            height, width = movingai.load_grid(path).shape
        except PolynavError:
            continue
        if height <= MAX_CELLS and width <= MAX_CELLS:
            found.append(path)
    return found


def run_map(path: Path, goals: int, walkers: int, seed: int) -> dict[str, Any]:
    """Drive one world's goals; its figures."""
    options = FromMapOptions(points=goals, walkers=walkers, seed=seed)
    planned = plan_world(path.stem, load_plan(path, options), options, allow_fewer=True)
    world = to_world(planned, options)
    floor = world.floors[0]
    stack = StackConfig()
    top_speed = stack.controller.max_linear_velocity
    static = Costmap.from_map(floor.map, CostmapConfig(obstacle_layer=False))
    planner = GridPlanner(stack.planner)
    driver = simulate(world, seed=seed, people=walkers > 0, stack_config=stack)
    driver.run(1.0)
    reached = 0
    efficiencies = []
    closest = math.inf
    sim_start, wall_start = driver.now, time.perf_counter()
    for point in floor.points[1:]:
        start = driver.sim.true_pose
        try:
            optimal = planner.plan(static, start, point.pose).length
        except PolynavError:
            optimal = math.nan
        began = driver.now
        driver.stack.go_to(point.pose, driver.now)
        end = driver.now + TIMEOUT
        while not driver.stack.navigator.state.finished and driver.now < end:
            driver.step()
            true = driver.sim.true_pose
            for person in driver.sim.people_poses():
                closest = min(closest, math.hypot(person.x - true.x, person.y - true.y))
        if driver.stack.navigator.state is NavigationState.SUCCEEDED:
            reached += 1
            if optimal > 0.5:
                efficiencies.append((driver.now - began) / (optimal / top_speed))
    wall = time.perf_counter() - wall_start
    efficiencies.sort()
    return {
        "map": path.name,
        "goals": len(floor.points) - 1,
        "reached": reached,
        "path_efficiency_median": efficiencies[len(efficiencies) // 2] if efficiencies else None,
        "collisions": len(driver.sim.collisions),
        "closest_person_m": None if math.isinf(closest) else round(closest, 3),
        "real_time_factor": (driver.now - sim_start) / wall if wall > 0 else math.inf,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="polynav bench nav", description=__doc__.splitlines()[0])
    parser.add_argument("--maps", type=Path, default=DATA, help="folder of MovingAI .map files")
    parser.add_argument("--limit", type=int, default=None, help="only the first N maps")
    parser.add_argument("--goals", type=int, default=20)
    parser.add_argument("--walkers", type=int, default=3)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    args = parser.parse_args(argv)
    maps = _maps(args.maps) if args.maps.is_dir() else []
    if args.limit is not None:
        maps = maps[: args.limit]
    if not maps:
        print(f"polynav bench nav: no MovingAI maps of at most {MAX_CELLS} x {MAX_CELLS} cells in "
              f"{args.maps} (data/movingai/ in the repository has them)", file=sys.stderr)
        return 2
    rows = []
    print(f"polynav bench nav: {len(maps)} maps at 1 m per cell, {args.goals} goals and "
          f"{args.walkers} walkers each, seed {args.seed}, Python {platform.python_version()}")
    print(f"{'map':24s}{'reached':>10s}{'efficiency':>12s}{'collisions':>12s}"
          f"{'closest':>9s}{'RTF':>7s}")
    for path in maps:
        try:
            row = run_map(path, args.goals, args.walkers, args.seed)
        except PolynavError as exc:
            print(f"{path.name:24s} skipped: {exc}")
            continue
        rows.append(row)
        eff = row["path_efficiency_median"]
        close = row["closest_person_m"]
        print(f"{row['map']:24s}{row['reached']:>5d}/{row['goals']:<4d}"
              f"{'-' if eff is None else f'{eff:.2f}':>12s}{row['collisions']:>12d}"
              f"{'-' if close is None else f'{close:.2f}':>9s}{row['real_time_factor']:>7.1f}",
              flush=True)
    goals = sum(r["goals"] for r in rows)
    reached = sum(r["reached"] for r in rows)
    effs = sorted(r["path_efficiency_median"] for r in rows if r["path_efficiency_median"])
    closests = [r["closest_person_m"] for r in rows if r["closest_person_m"] is not None]
    overall = {
        "maps": len(rows),
        "goals": goals,
        "reached": reached,
        "success_rate": reached / goals if goals else 0.0,
        "path_efficiency_median": effs[len(effs) // 2] if effs else None,
        "collisions": sum(r["collisions"] for r in rows),
        "closest_person_m": min(closests) if closests else None,
        "real_time_factor_min": min((r["real_time_factor"] for r in rows), default=0.0),
    }
    print(f"overall: {reached}/{goals} goals ({100.0 * overall['success_rate']:.1f} %), "
          f"median efficiency {overall['path_efficiency_median']}, "
          f"{overall['collisions']} collisions, closest approach to a person "
          f"{overall['closest_person_m']} m, slowest real-time factor "
          f"{overall['real_time_factor_min']:.1f}")
    if args.json:
        print(json.dumps({"seed": args.seed, "maps": rows, "overall": overall}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
