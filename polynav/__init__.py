"""polynav: open indoor robot navigation that speaks the commercial robots' network dialects.

The package is layered (see DESIGN.md): ``geometry``, ``maps``, ``planning`` and ``control`` are
the pure core; ``localization`` and ``nav`` are services advanced on a clock; ``robot`` holds the
robot interface and its backends (the simulator first).
"""

import os as _os

__version__ = "0.1.0"

# One BLAS thread, unless the user chose otherwise; it takes effect when polynav is imported
# before numpy (``polynav`` and ``python -m polynav`` do, and so does the test suite). polynav's
# arrays are small (the longest are a pose graph's residuals, about 1e4 numbers) and its own
# threads and processes already use the cores: OpenBLAS splits a dot product of more than 1e4
# numbers over worker threads, and on a busy machine each such call then waits for a worker's
# time slice. The pose-graph solve (scipy's LSMR takes a vector norm per iteration) spent 2 ms
# per norm that way instead of 5 us, half the time of the floor-1 exploration test.
_os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
