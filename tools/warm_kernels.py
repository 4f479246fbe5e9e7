"""Compile every numba kernel into numba's on-disk cache, in two processes side by side.

``make test`` runs this before pytest. On a fresh clone (CI) there is no cache yet: without this
step each pytest-xdist worker compiled the same kernels at once, and every ``polynav run`` a test
started before the cache was written compiled them again (about a minute of a core each). Here
they are compiled once, split across both cores; with the cache in place this takes a second.
"""

from __future__ import annotations

import importlib
import sys
import time
from concurrent.futures import ProcessPoolExecutor

#: The modules whose ``warm_up`` is called, in two groups of about equal compile time (the
#: runtime's own ``warm_up`` is not split, and planning alone is half of it). Each warm-up
#: compiles the kernels it calls too (path_kernels the control collision kernels).
GROUPS = (
    ("polynav.planning.registry",),
    ("polynav.mapping.slam", "polynav.maps.costmap", "polynav.localization.pose_tracker",
     "polynav.robot.sim", "polynav.control.path_kernels", "polynav.footprint.checks"),
)


def warm(modules: tuple[str, ...]) -> float:
    start = time.perf_counter()
    for name in modules:
        importlib.import_module(name).warm_up()
    return time.perf_counter() - start


def main() -> int:
    start = time.perf_counter()
    with ProcessPoolExecutor(len(GROUPS)) as pool:
        took = list(pool.map(warm, GROUPS))
    print(f"numba kernels compiled or loaded in {time.perf_counter() - start:.1f} s "
          f"({', '.join(f'{t:.1f} s' for t in took)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
