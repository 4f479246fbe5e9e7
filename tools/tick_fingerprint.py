"""A fingerprint of what the robots do, and the CPU it costs: for changes meant only to be faster.

Three robots in the demo building, walkers on, run random cross-floor missions (through the
lifts, doors and traffic zones); every simulated second each robot's true pose and navigation
state go into a hash. A change that only makes the tick cheaper must print the same fingerprint:
the fleet benches are chaotic, so a change in the last bit of one float shows there only as
different missions, here at once. The CPU per robot-second it prints is noisy on a shared
machine: compare two trees by running them at the same time.

    .venv/bin/python tools/tick_fingerprint.py [--missions 4] [--profile FILE]

Another tree: ``PYTHONPATH=/path/to/tree .venv/bin/python /path/to/tree/tools/tick_fingerprint.py``.
"""

from __future__ import annotations

import argparse
import cProfile
import hashlib
import tempfile
import time
from pathlib import Path

import numpy as np

import polynav
from polynav.house.building import Building
from polynav.runtime.config import RuntimeConfig
from polynav.site import PointKind
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world

ROBOTS = 3
SEED = 11


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--missions", type=int, default=4, help="missions in all (default 4)")
    parser.add_argument("--profile", type=Path, help="write a cProfile of the run here")
    args = parser.parse_args(argv)
    print("code:", Path(polynav.__file__).parent)
    world = load_world("demo")
    digest = hashlib.sha256()
    with tempfile.TemporaryDirectory() as tmp, SiteStore.open(Path(tmp) / "data",
                                                              seed_world=world) as store:
        rng = np.random.default_rng(SEED)
        building = Building(store, world, robots=ROBOTS,
                            config=RuntimeConfig(people=True, seed=SEED))
        maps = [f.map_name for f in world.floors]
        general = {m: [p.name for p in store.points(map_name=m) if p.kind is PointKind.GENERAL]
                   for m in maps}
        last_second = -1

        def note_poses() -> None:
            nonlocal last_second
            now = building.runtimes[0].now()
            if int(now) == last_second:
                return
            last_second = int(now)
            for runtime in building.runtimes:
                status = runtime.status()
                digest.update(repr((round(now, 3), status.pose.x, status.pose.y,
                                    status.pose.theta, status.navigation_state)).encode())

        bound: dict[str, tuple[str, str]] = {}
        pending: dict[str, str] = {}
        outcomes: list[str] = []
        sent = 0
        profile = cProfile.Profile() if args.profile else None
        wall, cpu = time.perf_counter(), time.process_time()
        if profile is not None:
            profile.enable()
        while sent < args.missions or pending:
            for serial, runtime in zip(building.serials, building.runtimes, strict=True):
                if serial in pending or sent >= args.missions:
                    continue
                taken = {v for k, v in bound.items() if k != serial}
                options = [(m, g) for m in maps if m != runtime.map_name for g in general[m]
                           if (m, g) not in taken]
                bound[serial] = options[int(rng.integers(len(options)))]
                pending[serial] = building.send(serial, bound[serial][1], bound[serial][0])
                sent += 1

            def ended() -> bool:
                note_poses()
                return any(building.outcome(s, o) is not None for s, o in pending.items())

            if not building.advance_until(ended, 900.0):
                print("no mission ended within 900 s")
                return 1
            for serial, order in list(pending.items()):
                outcome = building.outcome(serial, order)
                if outcome is not None:
                    outcomes.append(outcome)
                    del pending[serial]
        if profile is not None:
            profile.disable()
            profile.dump_stats(args.profile)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        simulated = building.runtimes[0].now()
    print(f"simulated {simulated:.2f} s in {wall:.1f} s wall, {cpu:.1f} s CPU: "
          f"{1000.0 * cpu / simulated / ROBOTS:.1f} ms of CPU per robot-second")
    print("outcomes", outcomes)
    print("fingerprint", digest.hexdigest()[:16])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
