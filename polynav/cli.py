"""The ``polynav`` command line.

Benchmarks live in the repository's ``benchmarks/`` folder (STYLE R12); ``polynav bench AREA`` is a
thin front that loads ``benchmarks/AREA.py`` and calls its ``main(argv)``.
"""

from __future__ import annotations

import argparse
import importlib.util
import logging
import signal
import sys
import threading
from collections.abc import Sequence
from pathlib import Path

BENCH_AREAS = ("planner", "sim")
_BENCH_FILES = {"planner": "planner.py", "sim": "simulation.py"}


def _benchmarks_dir() -> Path:
    return Path(__file__).resolve().parent.parent / "benchmarks"


def _run_bench(area: str, argv: list[str]) -> int:
    path = _benchmarks_dir() / _BENCH_FILES[area]
    if not path.is_file():
        print(f"polynav bench: {path} not found (benchmarks run from a source checkout)",
              file=sys.stderr)
        return 2
    spec = importlib.util.spec_from_file_location(f"polynav_bench_{area}", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return int(module.main([*argv]) or 0)


def _run(args: argparse.Namespace) -> int:
    from polynav.runtime.demo_tour import run_demo_tour
    from polynav.worlds import load_world

    if args.speed <= 0:
        print("polynav run: --speed must be > 0", file=sys.stderr)
        return 2
    stop = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())
    world = load_world(args.world)
    print(f"polynav: simulating world {world.name!r} at {args.speed:g}x real time "
          "(Ctrl-C to stop)", flush=True)
    reached = run_demo_tour(
        world,
        speed=args.speed,
        seed=args.seed,
        people=not args.no_people,
        stop=stop,
        report=lambda line: print(line, flush=True),
    )
    print(f"polynav: stopped after {reached} goals", flush=True)
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="polynav", description=__doc__.splitlines()[0])
    parser.add_argument("-v", "--verbose", action="count", default=0, help="more logging")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser(
        "run",
        help="run the simulated robot on the demo site",
        description="Start the simulator with a world and tour its named points, logging progress.",
    )
    run.add_argument("--world", default="demo", help="built-in world name or folder path")
    run.add_argument("--speed", type=float, default=1.0, help="simulated time factor")
    run.add_argument("--seed", type=int, default=0, help="seed of every simulated noise source")
    run.add_argument("--no-people", action="store_true", help="no walkers in the simulation")
    bench = sub.add_parser(
        "bench",
        help="run a benchmark (planner, sim); extra arguments go to the benchmark",
        description="Run a benchmark from benchmarks/. Pass --help after the area for its options.",
    )
    bench.add_argument("area", choices=BENCH_AREAS)
    bench.add_argument("args", nargs=argparse.REMAINDER, help="arguments for the benchmark")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(list(sys.argv[1:] if argv is None else argv))
    logging.basicConfig(
        level=logging.WARNING - 10 * min(args.verbose, 2),
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
    )
    if args.command == "bench":
        return _run_bench(args.area, args.args)
    if args.command == "run":
        return _run(args)
    parser.error(f"unknown command {args.command}")
    return 2
