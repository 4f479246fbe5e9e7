"""polynav runs numpy's BLAS on one thread unless told otherwise (``polynav/__init__.py`` says
why: on a busy machine each threaded vector norm of the pose-graph solve waited for a time slice).
"""

from __future__ import annotations

import ctypes
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
_CODE = "import os, polynav, numpy; print(os.environ['OPENBLAS_NUM_THREADS'])"


def _threads_after_import(**env: str) -> str:
    base = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    done = subprocess.run([sys.executable, "-c", _CODE], env={**base, "PYTHONPATH": str(ROOT),
                                                             **env},
                          capture_output=True, text=True, timeout=60.0, check=True)
    return done.stdout.strip()


def test_importing_polynav_asks_for_one_blas_thread_and_keeps_a_user_s_choice() -> None:
    assert _threads_after_import() == "1"
    assert _threads_after_import(OPENBLAS_NUM_THREADS="3") == "3"


def test_numpy_s_openblas_runs_one_thread_in_this_process() -> None:
    """The setting is read when numpy loads OpenBLAS: polynav must have been imported first
    (a plugin importing numpy earlier would silently bring the threads back)."""
    libs = sorted((Path(np.__file__).parent.parent / "numpy.libs").glob("libscipy_openblas*.so"))
    if not libs:
        pytest.skip("numpy is not linked with the scipy-openblas wheel's OpenBLAS")
    lib = ctypes.CDLL(str(libs[0]))
    getter = next((getattr(lib, name) for name in ("scipy_openblas_get_num_threads64_",
                                                   "scipy_openblas_get_num_threads")
                   if hasattr(lib, name)), None)
    if getter is None:
        pytest.skip(f"{libs[0].name} has no thread-count query")
    assert getter() == 1
