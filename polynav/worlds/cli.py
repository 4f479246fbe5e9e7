"""``polynav world from-map``: a simulation world from any ROS or MovingAI floor plan."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from polynav.errors import PolynavError
from polynav.robot.profile import load_profile
from polynav.worlds.from_map import FromMapOptions, write_world_from_map

EXIT_BAD_INPUT = 2


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:  # type: ignore[type-arg]
    """Add ``world from-map`` to the command line's sub-commands."""
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "world", help="make simulation worlds", description="Make simulation worlds."
    )
    sub = parser.add_subparsers(dest="world_command", required=True)
    make = sub.add_parser(
        "from-map", help="a world from a ROS (.yaml) or MovingAI (.map) floor plan",
        description="A one-floor world from a floor plan, with random reachable goal points "
        "and walkers; run it with `polynav run --world DIR` or `polynav bench sim --world DIR`.",
    )
    make.add_argument("map", type=Path, help="a ROS map .yaml or a MovingAI .map")
    make.add_argument("--out", type=Path, required=True, help="the world folder to create")
    make.add_argument("--cell", type=float, default=1.0,
                      help="metres per MovingAI cell (default %(default)s)")
    make.add_argument("--points", type=int, default=20, help="goal points (default %(default)s)")
    make.add_argument("--walkers", type=int, default=3, help="walkers (default %(default)s)")
    make.add_argument("--seed", type=int, default=0, help="random seed (default %(default)s)")
    make.add_argument("--robot", default=None,
                      help="the robot the world is for: a robot.yaml or a built-in profile name; "
                           "written into world.yaml, and points leave its body room to turn")
    return parser


def main(args: argparse.Namespace) -> int:
    """Run ``world from-map``: 0 once the world is written; 2, with one line on stderr and
    nothing written, on bad input (a missing or malformed plan, no room, bad options)."""
    try:
        robot = load_profile(args.robot) if args.robot is not None else None
        radius = {"robot_radius": robot.circumscribed_radius} if robot is not None else {}
        options = FromMapOptions(cell=args.cell, points=args.points, walkers=args.walkers,
                                 seed=args.seed, **radius)
        planned = write_world_from_map(args.map, args.out, options, robot)
    except PolynavError as exc:
        # One line, whatever the cause: a YAML parser's message spans several.
        reason = " ".join(str(exc).split())
        print(f"polynav world from-map: {reason}", file=sys.stderr)
        return EXIT_BAD_INPUT
    print(f"polynav world: {args.out}: {planned.grid.info.width} x {planned.grid.info.height} "
          f"cells at {planned.grid.info.resolution:g} m, {len(planned.points)} points, "
          f"{len(planned.walkers)} walkers")
    return 0
