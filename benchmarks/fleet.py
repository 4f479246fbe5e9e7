"""Fleet benchmark: N robots in one building doing random missions for a fixed simulated time.

Each robot runs the full stack (ray-cast lidar that sees the other robots, localization,
costmap, planner, controller) in one simulated world on one clock, under the fleet's traffic
rule (narrow passages leased one robot at a time, docs/fleet.md). Whenever a robot is idle it is
sent a fleet order (VDA 5050-shaped) to a random point of its floor other than the one it stands
at, that no other robot stands within 1 m of or is bound for (any floor with ``--cross-floor``:
through the lifts). (Drawn from every point, a robot was sent to where it stood 5-9 times an hour
at 10 robots: missions that counted as done at once; drawn from the points no robot was bound
for, one was sent to where another, bound elsewhere, still stood waiting for a corridor.)
Figures: missions completed per simulated hour, success rate, mean traffic and lift wait,
collisions, deadlocks (a mission that does not end within ``--mission-timeout``), real-time
factor, CPU per robot.

Targets (issue 11): success 100 %, collisions 0, no deadlock; 10 robots at least 3x real time
on one core. Run with ``polynav bench fleet --robots N [--hours H] [--seed S] [--json]``.

With ``--transport mqtt --processes P [--agents full|kinematic]`` the robots are spread over P
processes on a real broker and the missions go over MQTT (``benchmarks/fleet_mqtt.py``).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import logging
import math
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from polynav.house.building import Building
from polynav.runtime.config import RuntimeConfig
from polynav.site import Point, PointKind
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world

BUDGET_REAL_TIME_FACTOR = 3.0  # for 10 robots on one core
BUDGET_SUCCESS = 1.0


def _commit() -> str | None:
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"],
                             cwd=Path(__file__).resolve().parent, capture_output=True, text=True,
                             check=True)
    except (OSError, subprocess.CalledProcessError):
        return None
    return out.stdout.strip() or None


def _starts(store: SiteStore, world_maps: list[str], robots: int) -> list[Point]:
    """Start points spread over the floors: general points, every other one, floor by floor,
    so that robots do not start packed together."""
    by_map = {name: [p for p in store.points(map_name=name) if p.kind is PointKind.GENERAL]
              for name in world_maps}
    spread = [p for name in world_maps for p in by_map[name][::2]]
    spread += [p for name in world_maps for p in by_map[name][1::2]]
    if robots > len(spread):
        raise SystemExit(f"polynav bench fleet: {robots} robots but only {len(spread)} points")
    return spread[:robots]


def _stood_on(building: Building, where: dict[tuple[str, str], tuple[float, float]],
              reach: float = 1.0) -> set[tuple[str, str]]:
    """The points some robot stands within ``reach`` [m] of: one bound elsewhere has often not
    left yet (waiting for a corridor, say), and a dispatcher does not send a robot there."""
    stood: set[tuple[str, str]] = set()
    for serial in building.serials:
        runtime = building.agent(serial).runtime
        pose = runtime.status().pose
        for (map_name, name), (x, y) in where.items():
            if map_name == runtime.map_name and math.hypot(x - pose.x, y - pose.y) <= reach:
                stood.add((map_name, name))
    return stood


def _how_it_stands(building: Building, serial: str, goal_map: str,
                   goal: tuple[float, float] | None) -> str:
    """Where a robot whose mission timed out stands and what it waits for: the trace of a
    timeout (a queue for a zone, a walker in a doorway, a goal it cannot reach)."""
    agent = building.agent(serial)
    runtime = agent.runtime
    pose = runtime.status().pose
    stack = runtime.navigation_stack
    state = stack.navigator.state.value if stack is not None else "no stack"
    away = (f", {math.hypot(goal[0] - pose.x, goal[1] - pose.y):.1f} m from its goal"
            if goal is not None and runtime.map_name == goal_map else "")
    held = ",".join(agent.traffic.held) or "nothing"
    return (f"{runtime.map_name} ({pose.x:.1f}, {pose.y:.1f}){away}, {state}, waiting for "
            f"{agent.traffic.waiting_for or 'nothing'}, holding {held}")


def run(args: argparse.Namespace) -> dict[str, Any]:
    world = load_world(args.world)
    with tempfile.TemporaryDirectory() as tmp, SiteStore.open(
            Path(tmp) / "data", seed_world=world) as store:
        maps = [f.map_name for f in world.floors]
        starts = _starts(store, maps, args.robots)
        building = Building(store, world, robots=args.robots, starts=starts,
                            config=RuntimeConfig(people=args.people, seed=args.seed))
        goals = {name: [p.name for p in store.points(map_name=name)
                        if p.kind is PointKind.GENERAL] for name in maps}
        where = {(p.map_name, p.name): (p.pose.x, p.pose.y) for name in maps
                 for p in store.points(map_name=name)}
        rng = np.random.default_rng(args.seed)
        bound = {serial: (p.map_name, p.name) for serial, p in zip(building.serials, starts,
                                                                    strict=True)}
        pending: dict[str, tuple[str, float]] = {}
        done = succeeded = deadlocks = 0
        failures: list[str] = []
        building.advance(1.0)  # warm the trackers: start-up is not the steady state
        sim_start, wall_start, cpu_start = building.now(), time.perf_counter(), time.process_time()
        end = sim_start + args.hours * 3600.0
        while building.now() < end:
            for serial in building.serials:
                if serial in pending:
                    continue
                here = building.agent(serial).runtime.map_name or bound[serial][0]
                choices = maps if args.cross_floor else [here]
                taken = set(bound.values()) | _stood_on(building, where)
                options = [(m, g) for m in choices for g in goals[m] if (m, g) not in taken]
                target = options[int(rng.integers(len(options)))]
                bound[serial] = target
                pending[serial] = (building.send(serial, target[1], target[0]), building.now())
            building.advance_until(
                lambda: any(building.outcome(s, o) is not None
                            or building.now() - t0 > args.mission_timeout
                            for s, (o, t0) in pending.items()),
                timeout=max(0.0, end - building.now()))
            for serial, (order_id, t0) in list(pending.items()):
                outcome = building.outcome(serial, order_id)
                if outcome is None and building.now() - t0 > args.mission_timeout:
                    deadlocks += 1
                    stance = _how_it_stands(building, serial, bound[serial][0],
                                            where.get(bound[serial]))
                    outcome = f"failed: no end within the mission timeout ({stance})"
                    building.master.cancel_order(serial)
                if outcome is None:
                    continue
                del pending[serial]
                done += 1
                ok = outcome == "succeeded"
                succeeded += ok
                if not ok:
                    failures.append(f"{serial} -> {bound[serial][0]}/{bound[serial][1]}: "
                                    f"{outcome}")
                if args.verbose:
                    print(f"t={building.now():8.1f}s {serial} {bound[serial][0]}/"
                          f"{bound[serial][1]}: {outcome}", flush=True)
        sim_seconds = building.now() - sim_start
        wall = time.perf_counter() - wall_start
        cpu = time.process_time() - cpu_start
        traffic = [a.traffic for a in building.agents]
        waits = sum(t.waits for t in traffic)
        collisions = sum(len(r.simulation.collisions) for r in building.runtimes)
        if args.verbose:
            for serial, r in zip(building.serials, building.runtimes, strict=True):
                for c in r.simulation.collisions:
                    print(f"t={c.stamp:8.1f}s {serial} touched a {c.obstacle} at "
                          f"({c.pose.x:.2f}, {c.pose.y:.2f}) (on {r.map_name} at the end)",
                          flush=True)
        lift_waits = [w for r in building.runtimes for w in r.lift_waits]
        building.stop()
    return {
        "world": args.world,
        "robots": args.robots,
        "people": args.people,
        "cross_floor": args.cross_floor,
        "seed": args.seed,
        "sim_hours": round(sim_seconds / 3600.0, 4),
        "missions": done,
        "succeeded": succeeded,
        "success_rate": round(succeeded / done, 4) if done else 0.0,
        "missions_per_hour": round(succeeded / (sim_seconds / 3600.0), 1) if sim_seconds else 0.0,
        "failed": failures,
        "deadlocks": deadlocks,
        "collisions": collisions,
        "traffic_waits": waits,
        "mean_traffic_wait_s": round(sum(t.wait_time for t in traffic) / waits, 2) if waits
        else 0.0,
        "traffic_rejections": sum(t.rejections for t in traffic),
        "lift_rides": len(lift_waits),
        "mean_lift_wait_s": round(sum(lift_waits) / len(lift_waits), 2) if lift_waits else 0.0,
        "max_lift_wait_s": round(max(lift_waits), 2) if lift_waits else 0.0,
        "real_time_factor": round(sim_seconds / wall, 2) if wall > 0 else math.inf,
        "cpu_per_robot": round(cpu / sim_seconds / args.robots, 4) if sim_seconds else 0.0,
        "budget_real_time_factor": BUDGET_REAL_TIME_FACTOR,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="polynav bench fleet",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--robots", type=int, default=3, help="how many robots (default 3)")
    parser.add_argument("--hours", type=float, default=1.0, help="simulated hours (default 1)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--world", default="demo")
    parser.add_argument("--people", action="store_true", help="let the walkers walk")
    parser.add_argument("--cross-floor", action="store_true",
                        help="missions to any floor, through the lifts; default: the robot's "
                        "floor")
    parser.add_argument("--mission-timeout", type=float, default=600.0,
                        help="a mission not ended after this many simulated seconds is a "
                        "deadlock (default 600)")
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    parser.add_argument("--transport", choices=("inproc", "mqtt"), default="inproc",
                        help="inproc (default): one process; mqtt: robots in --processes "
                        "processes on a real Mosquitto, missions over MQTT")
    parser.add_argument("--processes", type=int, default=2,
                        help="worker processes with --transport mqtt (default 2)")
    parser.add_argument("--agents", choices=("full", "kinematic"), default="full",
                        help="full (default): every robot's whole stack; kinematic: the light "
                        "mode, vehicles that follow orders kinematically (--transport mqtt)")
    parser.add_argument("--speed", type=float, default=1.0,
                        help="simulated seconds per wall second with --transport mqtt "
                        "(default 1)")
    parser.add_argument("--sim-seconds", type=float, default=None,
                        help="simulated seconds to run (instead of --hours)")
    parser.add_argument("--visualization-period", type=float, default=0.25,
                        help="[s] between two visualization messages of a robot, which the "
                        "other processes draw it from (--transport mqtt; default 0.25)")
    parser.add_argument("--max-wall", type=float, default=None,
                        help="[s] with --transport mqtt, end after this much wall time even if "
                        "the simulated time is not reached (a machine that cannot keep the "
                        "pace); the figures cover the simulated time reached")
    parser.add_argument("--mission-rate", type=float, default=None, metavar="PER_S",
                        help="with --transport mqtt, missions posted per second of site time "
                        "at most (default: one per robot per minute)")
    parser.add_argument("--broker-restart-at", type=float, default=None, metavar="S",
                        help="[s of site time] with --transport mqtt, kill the broker then and "
                        "start it again (every mission must still end once)")
    parser.add_argument("--kinematic-speed", type=float, default=1.0,
                        help="[m/s] the light vehicles drive at (default 1)")
    parser.add_argument("--lift-wait", type=float, default=30.0,
                        help="[s] a light vehicle's change of floor (default 30)")
    parser.add_argument("-v", "--verbose", action="store_true", help="print every mission")
    args = parser.parse_args(argv)
    if args.robots < 1:
        parser.error("--robots must be >= 1")
    if not args.hours > 0.0:
        parser.error("--hours must be > 0")
    if args.sim_seconds is not None:
        if not args.sim_seconds > 0.0:
            parser.error("--sim-seconds must be > 0")
        args.hours = args.sim_seconds / 3600.0
    args.sim_seconds = args.hours * 3600.0
    logging.getLogger("polynav").setLevel(logging.ERROR)
    if args.transport == "mqtt":
        return _main_mqtt(parser, args)
    if args.agents != "full":
        parser.error("--agents kinematic needs --transport mqtt")
    figures = run(args)
    print(f"{figures['robots']} robots, {figures['sim_hours']:.2f} simulated h: "
          f"{figures['missions']} missions, {figures['succeeded']} succeeded "
          f"({figures['success_rate'] * 100:.1f} %), {figures['missions_per_hour']:.1f} per hour")
    print(f"collisions {figures['collisions']}, deadlocks {figures['deadlocks']}, traffic waits "
          f"{figures['traffic_waits']} (mean {figures['mean_traffic_wait_s']:.1f} s), "
          f"lift rides {figures['lift_rides']} (mean wait {figures['mean_lift_wait_s']:.1f} s, "
          f"max {figures['max_lift_wait_s']:.1f} s)")
    print(f"real-time factor {figures['real_time_factor']:.2f}x, CPU per robot "
          f"{figures['cpu_per_robot'] * 100:.1f} % of a core at 1x")
    for failure in figures["failed"]:
        print(f"  FAILED {failure}")
    fast_enough = figures["robots"] < 10 or (
        figures["real_time_factor"] >= BUDGET_REAL_TIME_FACTOR)
    passed = (figures["success_rate"] >= BUDGET_SUCCESS and figures["collisions"] == 0
              and figures["deadlocks"] == 0 and fast_enough)
    if args.json:
        print(json.dumps({**figures, "pass": passed, "commit": _commit(),
                          "machine": platform.platform()}))
    return 0


def _main_mqtt(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    if not 1 <= args.processes <= args.robots:
        parser.error("--processes must be between 1 and --robots")
    if not args.speed > 0.0:
        parser.error("--speed must be > 0")
    if not args.visualization_period > 0.0:
        parser.error("--visualization-period must be > 0")
    if args.mission_rate is not None and not args.mission_rate > 0.0:
        parser.error("--mission-rate must be > 0")
    path = Path(__file__).resolve().parent / "fleet_mqtt.py"
    spec = importlib.util.spec_from_file_location("polynav_bench_fleet_mqtt", path)
    assert spec is not None and spec.loader is not None
    mqtt = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mqtt  # its dataclasses look their module up
    spec.loader.exec_module(mqtt)
    figures = mqtt.run_mqtt(args, _starts)
    for line in mqtt.report(figures):
        print(line)
    if args.json:
        kinematic_ok = (figures["order_latency_p99_ms"] is not None
                        and figures["order_latency_p99_ms"] <= figures[
                            "budget_order_latency_p99_ms"]
                        and figures["lost_state_messages"] == 0)
        full_ok = (figures["success_rate"] >= BUDGET_SUCCESS and figures["collisions"] == 0
                   and figures["deadlocks"] == 0)
        passed = kinematic_ok if args.agents == "kinematic" else full_ok
        print(mqtt.dumps({**figures, "pass": passed, "commit": _commit(),
                          "machine": platform.platform()}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
