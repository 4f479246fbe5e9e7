"""Open-list keys and a binary min-heap of them, on a preallocated int64 array.

Every open-list entry is two int64 words ``(key, tie)``, stored side by side so that one cache
line holds four entries (three parallel arrays cost three cache misses per heap level):

* ``key`` is ``f`` quantised to ``2**-32`` cells (:func:`f_key`). Floating-point sums of 1 and
  sqrt 2 along different but equally long paths differ in the last bits; unquantised, those
  differences decide the order among equal-``f`` nodes as if at random, and on open floors the
  search floods the whole parallelogram of optimal paths. With the quantum, equal ``f`` compare
  equal and the tie-break below works. On a uniform-cost grid two *different* path lengths
  ``a + b sqrt 2`` differ by far more than ``2**-32`` (about ``1 / (3 |b|)``), so the order, and
  the cost found, stay exact; with cost weights the quantum can at worst misorder costs closer
  than ``2**-32``, a bound far below any tolerance that matters.
* ``tie`` is the float32 bit pattern of ``h`` in the high half (non-negative floats order like
  their bit patterns) and the cell index in the low half. Among equal keys the smaller ``h``,
  i.e. the larger ``g``, comes first: the deeper node is nearer the goal, so the search runs
  straight along one optimal path instead of widening across all of them.

Numba increments and decrements the reference count of every array passed to a jitted call, with
atomic instructions; called once per expansion, that alone took 40 % of the A* time. So the hot
search loops inline their heap steps, and the functions here serve the cold paths (building a
heap from a batch, compaction) and the slower searches (Theta*), where a call is noise.
"""

from __future__ import annotations

import logging

import numba
import numpy as np
import numpy.typing as npt
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

log = logging.getLogger(__name__)

KEY_SCALE = 4294967296.0
"""``2**32`` quanta per cell of cost in a key."""

CELL_MASK = 0xFFFFFFFF
"""The low half of a tie word: the flat cell index (grids of fewer than ``2**31`` cells)."""

MAX_F = 2.0**30
"""Largest ``f`` [cells] a key holds with room to spare (``2**30 * 2**32 < 2**63``)."""


@intrinsic
def _float32_bits(typingctx, value):  # type: ignore[no-untyped-def]
    sig = types.int32(types.float32)

    def codegen(context, builder, signature, args):  # type: ignore[no-untyped-def]
        return builder.bitcast(args[0], ir.IntType(32))

    return sig, codegen


@numba.njit(cache=True, nogil=True)
def f_key(f: float) -> int:
    """The heap key of an ``f`` value [cells]: ``f`` rounded to a multiple of ``2**-32``."""
    return int(f * KEY_SCALE + 0.5)


@numba.njit(cache=True, nogil=True)
def tie_key(h: float, cell: int) -> int:
    """The tie word: float32 bits of ``h`` above the cell index (smaller ``h`` first)."""
    # numba supplies the intrinsic's typing context: the call takes the value only.
    bits: int = _float32_bits(np.float32(h))  # type: ignore[call-arg]
    return int((np.int64(bits) << 32) | cell)


@numba.njit(cache=True, nogil=True)
def push(heap: npt.NDArray[np.int64], n: int, key: int, tie: int) -> int:
    """Insert ``(key, tie)`` into a heap of ``n`` entries (room assumed). Returns ``n + 1``."""
    j = n
    while j > 0:
        p = (j - 1) >> 1
        pk = heap[2 * p]
        pt = heap[2 * p + 1]
        if not (key < pk or (key == pk and tie < pt)):
            break
        heap[2 * j] = pk
        heap[2 * j + 1] = pt
        j = p
    heap[2 * j] = key
    heap[2 * j + 1] = tie
    return n + 1


@numba.njit(cache=True, nogil=True)
def sift_down(heap: npt.NDArray[np.int64], j: int, n: int, key: int, tie: int) -> None:
    """Place ``(key, tie)`` at slot ``j`` or below, restoring the order of ``heap[:n]``."""
    while True:
        c = 2 * j + 1
        if c >= n:
            break
        ck = heap[2 * c]
        ct = heap[2 * c + 1]
        if c + 1 < n:
            rk = heap[2 * c + 2]
            rt = heap[2 * c + 3]
            if rk < ck or (rk == ck and rt < ct):
                ck = rk
                ct = rt
                c += 1
        if not (ck < key or (ck == key and ct < tie)):
            break
        heap[2 * j] = ck
        heap[2 * j + 1] = ct
        j = c
    heap[2 * j] = key
    heap[2 * j + 1] = tie


@numba.njit(cache=True, nogil=True)
def pop(heap: npt.NDArray[np.int64], n: int) -> int:
    """Remove the top entry (read ``heap[0]``, ``heap[1]`` first). Returns ``n - 1``."""
    n -= 1
    if n > 0:
        sift_down(heap, 0, n, heap[2 * n], heap[2 * n + 1])
    return n


@numba.njit(cache=True, nogil=True)
def heapify(heap: npt.NDArray[np.int64], n: int) -> None:
    """Order ``heap[:n]`` in place (Floyd's bottom-up construction, ``O(n)``)."""
    for j in range((n - 2) // 2, -1, -1):
        sift_down(heap, j, n, heap[2 * j], heap[2 * j + 1])


def warm_up() -> None:
    """Compile the heap functions on tiny inputs."""
    heap = np.empty(8, dtype=np.int64)
    n = push(heap, 0, f_key(2.0), tie_key(1.0, 3))
    n = push(heap, n, f_key(1.0), tie_key(0.5, 2))
    heapify(heap, n)
    pop(heap, n)
