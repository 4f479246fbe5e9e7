"""Global planner benchmark: polynav's A* against pyastar2d and scikit-image on the same queries.

Two sets of queries (DESIGN §8: faster than pyastar2d, a C++ A*, on random pairs on a 2000 x 2000
map, with costs equal to the MovingAI optimal lengths):

* **movingai**: every line of every ``.scen`` file in ``--maps`` (each beside its ``.map``),
  on the binary grid; our cost is checked against column 9 wherever that is a real optimum
  (placeholder 0.0 lines are timed but not checked);
* **nav2**: the three 2000 x 2000 maps of Nav2's planner benchmark, with its start/goal protocol
  (Nav2's ``tools/planner_benchmarking/metrics.py``: Python ``random`` seeded once with 33, row
  then column uniform in ``[100, N - 100]``, costmap cost below 210, goal more than 3 m away,
  100 pairs per map that our planner solves) on a costmap with Nav2's inflation (robot radius
  0.22 m, inflation radius 0.7 m, cost scaling 3.0), and the planner's default cost weight.

The three planners get equivalent inputs: ours the uint8 costs; pyastar2d float32 weights
``1 + w c / 252`` (1 on MovingAI) with ``inf`` for cells at or above INSCRIBED, called through its
raw entry point with the weights flattened once per map (its Python wrapper would copy and scan
the whole map on every call, which is not the search); scikit-image ``route_through_array``
(``fully_connected=True, geometric=True``) the same weights as float64. Note the models differ:
pyastar2d prices a diagonal step like an orthogonal one and both it and scikit-image cut
corners, so only our costs are compared with the references. scikit-image searches the whole
grid per query (seconds on 2000 x 2000), so it runs on a deterministic subsample of the same
queries (``--skimage-per-map``), reported with its own count.

``polynav_plan`` (nav2 only) is the full ``GridPlanner.plan``: search, shortcutting and 5 cm
densification, from cell centres.

Run with ``polynav bench planner [--json] [--maps DIR] [--limit N] [--nav2-dir DIR] [--no-nav2]``.
With ``--json`` the last line is one JSON object with the figures.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import random
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps import costs as cost_values
from polynav.maps.movingai import load_grid, load_scenarios
from polynav.planning import registry
from polynav.planning.astar import AStar
from polynav.planning.grid_planner import GridPlanner, GridPlannerConfig
from polynav.planning.grid_search import step_multipliers

REPO = Path(__file__).resolve().parent.parent
DEFAULT_MAPS = REPO / "data" / "movingai"
DEFAULT_NAV2 = REPO / "data" / "nav2" / "planner_benchmark"
NAV2_MAPS = ("100by100_10", "100by100_15", "100by100_20")
NAV2_SEED = 33
NAV2_PAIRS = 100
NAV2_BORDER = 100
NAV2_MAX_COST = 210
NAV2_MIN_DISTANCE = 3.0
PLANNERS = ("polynav", "pyastar2d", "skimage")
LENGTH_TOLERANCE = 1e-6

Search = Callable[[tuple[int, int], tuple[int, int]], object]


class SetResult:
    """Timings [s] per planner and the cost check of one set of queries.

    A plain class, not a dataclass: ``polynav bench`` loads this file without registering it as
    a module, and dataclasses look their module up.
    """

    def __init__(self) -> None:
        self.queries = 0
        self.cost_mismatches = 0
        self.checked = 0
        self.times: dict[str, list[float]] = {p: [] for p in PLANNERS}

    def add(self, other: SetResult) -> None:
        self.queries += other.queries
        self.cost_mismatches += other.cost_mismatches
        self.checked += other.checked
        for name, values in other.times.items():
            self.times.setdefault(name, []).extend(values)


def _commit() -> str | None:
    try:
        out = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            cwd=REPO,
            capture_output=True,
            text=True,
            check=True,
        )
    except (OSError, subprocess.CalledProcessError):
        return None
    return out.stdout.strip() or None


class Rivals:
    """pyastar2d and scikit-image, when installed (benchmark-only extras, imported here)."""

    def __init__(self) -> None:
        try:
            import pyastar2d  # noqa: F401  (sets up the raw entry point's ctypes signature)
            import pyastar2d.astar as raw
        except ImportError:
            print("pyastar2d is not installed: its column stays empty", file=sys.stderr)
            self._pyastar: Any = None
        else:
            self._pyastar = raw.astar
        try:
            from skimage.graph import route_through_array
        except ImportError:
            print("scikit-image is not installed: its column stays empty", file=sys.stderr)
            self._skimage: Any = None
        else:
            self._skimage = route_through_array

    @property
    def has_pyastar2d(self) -> bool:
        return self._pyastar is not None

    @property
    def has_skimage(self) -> bool:
        return self._skimage is not None

    def pyastar2d(self, weights: npt.NDArray[np.float32]) -> Search:
        """A query function on this map; ``weights`` is the [row, col] float32 grid."""
        height, width = weights.shape
        flat = np.ascontiguousarray(weights, dtype=np.float32).ravel()
        run = self._pyastar

        def search(start: tuple[int, int], goal: tuple[int, int]) -> object:
            return run(flat, height, width, start[1] * width + start[0],
                       goal[1] * width + goal[0], True, 0)

        return search

    def skimage(self, weights: npt.NDArray[np.float64]) -> Search:
        grid = np.ascontiguousarray(weights, dtype=np.float64)
        run = self._skimage

        def search(start: tuple[int, int], goal: tuple[int, int]) -> object:
            return run(grid, (start[1], start[0]), (goal[1], goal[0]),
                       fully_connected=True, geometric=True)

        return search


def _ours(planner: AStar, values: npt.NDArray[np.uint8], table: npt.NDArray[np.float64]) -> Search:
    def search(start: tuple[int, int], goal: tuple[int, int]) -> object:
        return planner.search(values, start, goal, multipliers=table)

    return search


def _timed(search: Search, start: tuple[int, int], goal: tuple[int, int]) -> tuple[float, object]:
    began = time.perf_counter()
    found = search(start, goal)
    return time.perf_counter() - began, found


def _subsample(count: int, keep: int) -> set[int]:
    """Evenly spread query indices, the same on every run."""
    if keep <= 0:
        return set()
    if count <= keep:
        return set(range(count))
    return {int(round(v)) for v in np.linspace(0, count - 1, keep)}


def _weights(values: npt.NDArray[np.uint8], cost_weight: float) -> npt.NDArray[np.float64]:
    """Step weights equivalent to our multipliers: ``inf`` where we cannot go."""
    table = step_multipliers(cost_weight=cost_weight)
    return np.asarray(table[values])


def missing_data(maps: Path, nav2: Path | None) -> str | None:
    """Why the benchmark cannot run on these folders, or None: a benchmark with no queries
    would print a table of dashes and prove nothing."""
    pairs = [s for s in maps.glob("*.scen") if s.with_suffix(".map").is_file()]
    if not pairs:
        return (f"no MovingAI .scen/.map pairs in {maps} (the repository ships them in "
                f"{DEFAULT_MAPS.relative_to(REPO)}; --maps DIR names another folder)")
    if nav2 is not None and not any((nav2 / f"{n}.yaml").is_file() for n in NAV2_MAPS):
        return (f"none of the Nav2 maps {', '.join(NAV2_MAPS)} in {nav2} (shipped in "
                f"{DEFAULT_NAV2.relative_to(REPO)}; --nav2-dir DIR, or --no-nav2)")
    return None


def run_movingai(
    folder: Path, *, limit: int | None, skimage_per_map: int, rivals: Rivals
) -> SetResult:
    total = SetResult()
    table = step_multipliers(cost_weight=0.0)
    planner = AStar()
    for scen in sorted(folder.glob("*.scen")):
        map_file = scen.with_suffix(".map")
        if not map_file.is_file():
            print(f"{scen.name}: no {map_file.name} beside it, skipped", file=sys.stderr)
            continue
        blocked = load_grid(map_file)
        values = np.where(blocked, cost_values.LETHAL, cost_values.FREE).astype(np.uint8)
        scenarios = load_scenarios(scen)[:limit]
        weights = _weights(values, 0.0)
        ours = _ours(planner, values, table)
        rival_py = rivals.pyastar2d(weights.astype(np.float32)) if rivals.has_pyastar2d else None
        rival_sk = rivals.skimage(weights) if rivals.has_skimage else None
        sampled = _subsample(len(scenarios), skimage_per_map)
        result = SetResult()
        if scenarios:  # one untimed query: buffers sized, pages touched
            first = scenarios[0]
            ours((first.start_x, first.start_y), (first.goal_x, first.goal_y))
        for index, s in enumerate(scenarios):
            start, goal = (s.start_x, s.start_y), (s.goal_x, s.goal_y)
            elapsed, found = _timed(ours, start, goal)
            result.times["polynav"].append(elapsed)
            result.queries += 1
            if s.has_reference_length:
                result.checked += 1
                cost = getattr(found, "cost", math.inf)
                if not abs(cost - s.optimal_length) <= LENGTH_TOLERANCE:
                    result.cost_mismatches += 1
                    print(f"  MISMATCH {scen.stem} line {index + 1}: {cost} vs "
                          f"{s.optimal_length}", file=sys.stderr)
            if rival_py is not None:
                result.times["pyastar2d"].append(_timed(rival_py, start, goal)[0])
            if rival_sk is not None and index in sampled:
                result.times["skimage"].append(_timed(rival_sk, start, goal)[0])
        _print_row(scen.stem, result)
        total.add(result)
    return total


def _nav2_pairs(
    values: npt.NDArray[np.uint8], resolution: float, count: int, accept: Search
) -> list[tuple[tuple[int, int], tuple[int, int], float]]:
    """Nav2 ``metrics.py`` sampling: ((col, row) start, goal, our search time) per kept pair."""
    rng = random.Random(NAV2_SEED)
    size = values.shape[0]
    low, high = NAV2_BORDER, size - NAV2_BORDER

    def draw(start: tuple[int, int] | None) -> tuple[int, int]:
        while True:
            row = rng.randint(low, high)
            col = rng.randint(low, high)
            if values[row, col] >= NAV2_MAX_COST:
                continue
            if start is not None:
                distance = math.hypot((col - start[0]) * resolution,
                                      (row - start[1]) * resolution)
                if not distance > NAV2_MIN_DISTANCE:
                    continue
            rng.random()  # the heading, drawn but unused by a 2-D planner
            return (col, row)

    pairs = []
    while len(pairs) < count:
        start = draw(None)
        goal = draw(start)
        elapsed, found = _timed(accept, start, goal)
        if found is not None:
            pairs.append((start, goal, elapsed))
    return pairs


def run_nav2(
    folder: Path, *, limit: int | None, skimage_per_map: int, rivals: Rivals
) -> SetResult:
    from polynav.maps.costmap import Costmap, CostmapConfig
    from polynav.maps.ros_map import load_map

    total = SetResult()
    config = GridPlannerConfig()
    table = step_multipliers(cost_weight=config.cost_weight)
    planner = AStar()
    full = GridPlanner(config)
    total.times["polynav_plan"] = []
    for name in NAV2_MAPS:
        yaml_path = folder / f"{name}.yaml"
        if not yaml_path.is_file():
            print(f"{yaml_path} not found, skipped", file=sys.stderr)
            continue
        grid = load_map(yaml_path)
        costmap = Costmap.from_map(
            grid,
            CostmapConfig(robot_radius=0.22, inflation_radius=0.7, cost_scaling_factor=3.0),
        )
        values = np.ascontiguousarray(costmap.costs)
        info = costmap.info
        ours = _ours(planner, values, table)
        ours((NAV2_BORDER, NAV2_BORDER), (NAV2_BORDER, NAV2_BORDER))
        count = NAV2_PAIRS if limit is None else min(limit, NAV2_PAIRS)
        pairs = _nav2_pairs(values, info.resolution, count, ours)
        weights = _weights(values, config.cost_weight)
        rival_py = rivals.pyastar2d(weights.astype(np.float32)) if rivals.has_pyastar2d else None
        rival_sk = rivals.skimage(weights) if rivals.has_skimage else None
        sampled = _subsample(len(pairs), skimage_per_map)
        result = SetResult()
        result.times["polynav_plan"] = []
        for index, (start, goal, elapsed) in enumerate(pairs):
            result.queries += 1
            result.times["polynav"].append(elapsed)
            if rival_py is not None:
                result.times["pyastar2d"].append(_timed(rival_py, start, goal)[0])
            if rival_sk is not None and index in sampled:
                result.times["skimage"].append(_timed(rival_sk, start, goal)[0])
            a = Pose2D(*info.cell_to_world(*start))
            b = Pose2D(*info.cell_to_world(*goal))
            began = time.perf_counter()
            full.plan(costmap, a, b)
            result.times["polynav_plan"].append(time.perf_counter() - began)
        _print_row(name, result)
        total.add(result)
    return total


def _ms(values: Sequence[float], q: float) -> float | None:
    if not values:
        return None
    return round(float(np.percentile(np.asarray(values) * 1e3, q)), 4)


def summary(result: SetResult) -> dict[str, Any]:
    median = {name: _ms(values, 50) for name, values in result.times.items()}
    p95 = {name: _ms(values, 95) for name, values in result.times.items()}
    ours, theirs = median.get("polynav"), median.get("pyastar2d")
    ratio = round(ours / theirs, 3) if ours is not None and theirs else None
    return {
        "queries": result.queries,
        "cost_mismatches": result.cost_mismatches,
        "checked_costs": result.checked,
        "median_ms": median,
        "p95_ms": p95,
        "ratio_vs_pyastar2d": ratio,
        "skimage_queries": len(result.times.get("skimage", [])),
    }


def _fmt(value: float | None) -> str:
    return "-" if value is None else f"{value:.3f}"


def _print_row(name: str, result: SetResult) -> None:
    s = summary(result)
    cells = "  ".join(
        f"{p} {_fmt(s['median_ms'].get(p))}/{_fmt(s['p95_ms'].get(p))}" for p in result.times
    )
    print(f"  {name:<24} {s['queries']:>6} q  mismatches {s['cost_mismatches']}  "
          f"median/p95 ms: {cells}", flush=True)


def _print_set(name: str, s: dict[str, Any]) -> None:
    print(f"{name}: {s['queries']} queries, {s['cost_mismatches']} cost mismatches "
          f"({s['checked_costs']} checked)")
    for planner, median in s["median_ms"].items():
        count = s["skimage_queries"] if planner == "skimage" else s["queries"]
        print(f"    {planner:<13} median {_fmt(median):>9} ms   p95 {_fmt(s['p95_ms'][planner]):>9}"
              f" ms   ({count} queries)")
    print(f"    ratio polynav / pyastar2d (median): {s['ratio_vs_pyastar2d']}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="polynav bench planner",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    parser.add_argument("--maps", type=Path, default=DEFAULT_MAPS,
                        help="folder of MovingAI .map/.scen pairs")
    parser.add_argument("--limit", type=int, default=None, help="at most N queries per map")
    parser.add_argument("--nav2-dir", type=Path, default=DEFAULT_NAV2,
                        help="folder of the Nav2 planner-benchmark maps")
    parser.add_argument("--no-nav2", action="store_true", help="skip the Nav2 maps")
    parser.add_argument("--skimage-per-map", type=int, default=20,
                        help="queries per map also timed with scikit-image (0: none)")
    args = parser.parse_args(argv)
    if args.limit is not None and args.limit < 1:
        parser.error("--limit must be >= 1")
    missing = missing_data(args.maps, None if args.no_nav2 else args.nav2_dir)
    if missing:
        print(f"polynav bench planner: {missing}", file=sys.stderr)
        return 2

    began = time.perf_counter()
    registry.warm_up()  # compile before timing: start-up is not the steady state
    rivals = Rivals()
    print(f"warm-up {time.perf_counter() - began:.1f} s; MovingAI maps from {args.maps}")
    sets: dict[str, dict[str, Any]] = {}
    overall = SetResult()
    movingai = run_movingai(args.maps, limit=args.limit, skimage_per_map=args.skimage_per_map,
                            rivals=rivals)
    sets["movingai"] = summary(movingai)
    overall.add(movingai)
    if not args.no_nav2:
        print(f"Nav2 maps from {args.nav2_dir}")
        nav2 = run_nav2(args.nav2_dir, limit=args.limit, skimage_per_map=args.skimage_per_map,
                        rivals=rivals)
        sets["nav2"] = summary(nav2)
        nav2.times.pop("polynav_plan", None)
        overall.add(nav2)
    overall.times = {p: overall.times.get(p, []) for p in PLANNERS}
    figures = summary(overall)
    if not figures["queries"]:
        print("polynav bench planner: no query ran (every scenario file was empty?)",
              file=sys.stderr)
        return 2
    print()
    for name, s in sets.items():
        _print_set(name, s)
    _print_set("all", figures)
    print(f"total {time.perf_counter() - began:.0f} s")
    if args.json:
        nav2_ratio = sets.get("nav2", {}).get("ratio_vs_pyastar2d")
        figures.update(
            {
                "sets": sets,
                "budget": "nav2 ratio_vs_pyastar2d < 1 and 0 cost mismatches (DESIGN §8)",
                "pass": bool(figures["cost_mismatches"] == 0
                             and (nav2_ratio is None or nav2_ratio < 1.0)),
                "commit": _commit(),
                "machine": platform.platform(),
            }
        )
        print(json.dumps(figures))
    return 0 if figures["cost_mismatches"] == 0 else 1


if __name__ == "__main__":
    raise SystemExit(main())
