"""SLAM benchmark: relation error and real-time factor on the public 2-D laser logs.

For every dataset folder under ``--data`` (default ``../shared/data/slam`` beside the checkout)
that holds a Freiburg ``*.relations`` file, the SLAM runs on the folder's log with raw odometry
(for Intel, ``intel_raw_odom_scans.json``: raw odometry at each scan, stamps in the relations'
time base) and its trajectory is scored with the relation error of Kümmerle et al. (2009,
Cartographer's convention, :mod:`polynav.mapping.evaluation`):

* ``exact``: only the relations whose both stamps are scans of the log (90 on Intel), no
  interpolation: the headline figure;
* ``all``: every relation, poses interpolated between scans (the Intel scans are ~2.9 s apart,
  so this adds interpolation error; see the README before comparing with published figures).

The GMapping-corrected poses of the same scans (``*gmapping_corrected*.json``), the reference
that ships with the data, are scored the same way beside ours as a control (0.0368 m / 0.417°
on the 90 exact Intel relations). Folders with a log but no relations (``breezyslam_exp2``) are
run as smoke tests: wall time and real-time factor only.

Targets (issue 9): Intel mean translational error (exact) <= 0.037 m, real-time factor >= 20
on one core. The real-time factor is the log's duration over the wall time of the SLAM alone
(reading the log and warming numba up excluded).

Run with ``polynav bench slam [--data DIR] [--json]``; with ``--json`` each case also prints
one JSON line.
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from polynav.mapping import evaluation, logs
from polynav.mapping import slam as slam_module
from polynav.mapping.config import SlamConfig

REPO = Path(__file__).resolve().parent.parent
DEFAULT_DATA = REPO.parent / "shared" / "data" / "slam"
TARGET_ERROR = 0.037  # [m], the GMapping reference on the 90 exact Intel relations
TARGET_RTF = 20.0
LOG_PATTERNS = ("*raw_odom*.json", "*.clf", "*.log", "*.log.gz", "*.dat")
WHERE = """\
No SLAM logs found in {path}.
The benchmark needs the public logs described in shared/data/slam/README.md:
  intel/intel.relations, intel/intel_raw_odom_scans.json, intel/intel_gmapping_corrected_scans.json
      from github.com/xiaofeng419/SLAM-2D-LIDAR-SCAN @ d469252f (DataSet/RawData/intel.relations,
      DataSet/PreprocessedData/intel_gfs and intel_corrected_log, renamed); originally the
      Freiburg SLAM-evaluation page (ais.informatik.uni-freiburg.de/slamevaluation)
  breezyslam_exp2/exp2.dat
      from github.com/simondlevy/BreezySLAM @ 1170285c (examples/exp2.dat)
They are not shipped with polynav (unclear or GPL licences). Put them under one folder and pass
it with --data DIR."""


def _commit() -> str | None:
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO,
                             capture_output=True, text=True, check=True)
    except (OSError, subprocess.CalledProcessError):
        return None
    return out.stdout.strip() or None


def _find_log(folder: Path) -> Path | None:
    for pattern in LOG_PATTERNS:
        found = sorted(p for p in folder.glob(pattern) if "corrected" not in p.name)
        if found:
            return found[0]
    return None


def _poses(sensor_log: logs.SensorLog) -> tuple[np.ndarray, np.ndarray]:
    times = np.array([s.stamp for s in sensor_log.scans])
    poses = np.array([[s.odom.x, s.odom.y, s.odom.theta] for s in sensor_log.scans])
    return times, poses


def _score(times: np.ndarray, poses: np.ndarray,
           relations: evaluation.Relations) -> dict[str, dict[str, Any]]:
    out = {}
    for name, exact in (("exact", True), ("all", False)):
        result = evaluation.relation_error(times, poses, relations, exact_only=exact)
        out[name] = result.as_dict()
    return out


def run_case(log_path: Path, relations_path: Path | None) -> dict[str, Any]:
    """Run the SLAM on one log and score it (and its reference) if there are relations."""
    sensor_log = logs.read_log(log_path)
    began = time.perf_counter()
    slam = slam_module.replay(sensor_log, SlamConfig())
    wall = time.perf_counter() - began
    case: dict[str, Any] = {
        "name": log_path.parent.name,
        "log": log_path.name,
        "scans": len(sensor_log.scans),
        "skipped_lines": sensor_log.skipped_lines,
        "nodes": slam.node_count,
        "submaps": slam.submap_count,
        "loop_closures": slam.loop_closures,
        "rejected_loop_closures": slam.rejected_loop_closures,
        "duration_s": sensor_log.duration,
        "wall_s": wall,
        "rtf": sensor_log.duration / wall if wall > 0 else float("inf"),
    }
    if relations_path is None:
        case["pass"] = True
        return case
    relations = evaluation.parse_relations(relations_path.read_text().splitlines())
    traj = slam.trajectory()
    times = np.array([s.stamp for s in sensor_log.scans])
    poses = np.array([[p.x, p.y, p.theta] for p in traj])
    case["ours"] = _score(times, poses, relations)
    references = sorted(log_path.parent.glob("*gmapping_corrected*.json"))
    if references:
        case["reference"] = {"name": references[0].name,
                             **_score(*_poses(logs.read_log(references[0])), relations)}
    error = case["ours"]["exact"]["trans_mean"]
    case["budget"] = f"exact trans_mean <= {TARGET_ERROR} m and rtf >= {TARGET_RTF}"
    case["pass"] = bool(error <= TARGET_ERROR and case["rtf"] >= TARGET_RTF)
    return case


def _print_case(case: dict[str, Any]) -> None:
    print(f"{case['name']} ({case['log']}): {case['scans']} scans, {case['nodes']} nodes, "
          f"{case['submaps']} submaps, {case['loop_closures']} loop closures "
          f"({case['rejected_loop_closures']} rejected)")
    print(f"  wall {case['wall_s']:.1f} s for {case['duration_s']:.0f} s of log: "
          f"real-time factor {case['rtf']:.1f} (target {TARGET_RTF:g})")
    for who in ("ours", "reference"):
        if who not in case:
            continue
        for subset in ("exact", "all"):
            r = case[who][subset]
            print(f"  {who:9s} {subset:5s} ({r['relations']:4d} relations): "
                  f"{r['trans_mean']:.4f} ± {r['trans_std']:.4f} m, "
                  f"{r['rot_mean']:.3f} ± {r['rot_std']:.3f} deg")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="polynav bench slam",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=DEFAULT_DATA,
                        help="folder of dataset folders (default: %(default)s)")
    parser.add_argument("--json", action="store_true", help="one JSON line per case")
    args = parser.parse_args(argv)

    folders = sorted(p for p in args.data.iterdir() if p.is_dir()) if args.data.is_dir() else []
    cases = [(f, _find_log(f), next(iter(sorted(f.glob("*.relations"))), None)) for f in folders]
    cases = [(f, lg, rel) for f, lg, rel in cases if lg is not None]
    if not any(rel is not None for _, _, rel in cases):
        print(WHERE.format(path=args.data), file=sys.stderr)
        return 2
    began = time.perf_counter()
    slam_module.warm_up()  # compile before timing: start-up is not the steady state
    print(f"warm-up {time.perf_counter() - began:.1f} s; data from {args.data}")
    ok = True
    for _folder, log_path, relations_path in cases:
        assert log_path is not None
        case = run_case(log_path, relations_path)
        _print_case(case)
        ok = ok and case["pass"]
        if args.json:
            case.update({"commit": _commit(), "machine": platform.platform()})
            print(json.dumps(case))
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
