"""``polynav slam``: run the SLAM over a recorded log, and score a trajectory.

* ``polynav slam run LOG --out DIR`` writes ``DIR/map.pgm``, ``DIR/map.yaml`` (ROS map_server)
  and ``DIR/trajectory.txt`` (``timestamp x y theta`` per scan, the timestamp exactly as the
  log writes it);
* ``polynav slam eval TRAJECTORY RELATIONS [--time-offset S] [--exact-only] [--json]`` prints
  the relation error of Kümmerle et al. (2009), see :mod:`polynav.mapping.evaluation`.

:func:`add_parser` hangs both under the top-level parser; :func:`main` runs the one chosen.
"""

from __future__ import annotations

import argparse
import json
import logging
import time
from pathlib import Path

from polynav.mapping.errors import RelationsError

# The SLAM modules compile numba kernels and pull in scipy: they are imported in the commands
# that use them, so ``polynav --help`` and every other command stay quick to start.

log = logging.getLogger(__name__)


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:  # type: ignore[type-arg]
    """Add ``slam run`` and ``slam eval`` to the command line's sub-commands."""
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "slam", help="run the SLAM on a recorded log, or score a trajectory",
        description="Offline 2-D lidar SLAM on CARMEN, Intel JSON and Mines logs, and the "
        "Kümmerle et al. relation error.",
    )
    sub = parser.add_subparsers(dest="slam_command", required=True)
    run = sub.add_parser("run", help="build a map and trajectory from a log",
                         description="Run the SLAM over LOG and write map.pgm, map.yaml and "
                         "trajectory.txt into DIR.")
    run.add_argument("log", type=Path, help="CARMEN .log/.clf (plain or gzip), Intel .json, "
                     "or Mines .dat")
    run.add_argument("--out", type=Path, required=True, help="output folder (created)")
    score = sub.add_parser("eval", help="relation error of a trajectory",
                           description="Score TRAJECTORY (timestamp x y theta per line) against "
                           "a Freiburg .relations file.")
    score.add_argument("trajectory", type=Path)
    score.add_argument("relations", type=Path)
    score.add_argument("--time-offset", type=float, default=0.0,
                       help="seconds added to the trajectory's timestamps (default 0)")
    score.add_argument("--exact-only", action="store_true",
                       help="only relations whose both timestamps are trajectory timestamps")
    score.add_argument("--json", action="store_true", help="print one JSON object")
    return parser


def main(args: argparse.Namespace) -> int:
    """Run the ``slam`` sub-command in ``args``; PolynavErrors propagate to the caller."""
    if args.slam_command == "run":
        return _run(args)
    return _eval(args)


def write_trajectory(
    path: Path, stamps: list[str], poses: list[tuple[float, float, float]]
) -> None:
    """Write ``timestamp x y theta`` lines (timestamps verbatim)."""
    lines = [f"{t} {x:.6f} {y:.6f} {th:.6f}\n" for t, (x, y, th) in zip(stamps, poses,
                                                                         strict=True)]
    path.write_text("".join(lines), encoding="utf-8")


def _run(args: argparse.Namespace) -> int:
    from polynav.mapping import logs
    from polynav.mapping import slam as slam_module
    from polynav.mapping.config import SlamConfig
    from polynav.maps import ros_map

    sensor_log = logs.read_log(args.log)
    began = time.perf_counter()
    slam = slam_module.replay(sensor_log, SlamConfig())
    wall = time.perf_counter() - began
    args.out.mkdir(parents=True, exist_ok=True)
    ros_map.save_map(slam.render_map(), args.out / "map.yaml", image_format="pgm")
    poses = [(p.x, p.y, p.theta) for p in slam.trajectory()]
    write_trajectory(args.out / "trajectory.txt", [s.stamp_text for s in sensor_log.scans], poses)
    rtf = sensor_log.duration / wall if wall > 0 else float("inf")
    print(f"{len(sensor_log.scans)} scans ({sensor_log.skipped_lines} corrupt lines skipped), "
          f"{slam.node_count} nodes, {slam.submap_count} submaps, {slam.loop_closures} loop "
          f"closures ({slam.rejected_loop_closures} rejected); {wall:.1f} s, {rtf:.1f}x real time")
    print(f"wrote {args.out / 'map.pgm'}, {args.out / 'map.yaml'}, {args.out / 'trajectory.txt'}")
    return 0


def _eval(args: argparse.Namespace) -> int:
    from polynav.mapping import evaluation

    try:
        times, poses = evaluation.parse_trajectory(
            args.trajectory.read_text(encoding="utf-8").splitlines())
        relations = evaluation.parse_relations(
            args.relations.read_text(encoding="utf-8").splitlines())
    except OSError as exc:
        raise RelationsError(f"cannot read: {exc}") from exc
    result = evaluation.relation_error(times, poses, relations, time_offset=args.time_offset,
                                       exact_only=args.exact_only)
    if args.json:
        print(json.dumps(result.as_dict()))
    else:
        print(f"relations used: {result.relations} ({result.exact} exact, "
              f"{result.skipped} skipped)")
        print(f"translation: {result.trans_mean:.4f} ± {result.trans_std:.4f} m "
              f"(squared {result.trans2_mean:.5f} ± {result.trans2_std:.5f} m²)")
        print(f"rotation:    {result.rot_mean:.3f} ± {result.rot_std:.3f} deg "
              f"(squared {result.rot2_mean:.3f} ± {result.rot2_std:.3f} deg²)")
    return 0
