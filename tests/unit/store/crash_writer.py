"""A process that writes to a site store as fast as it can, to be killed by the crash tests.

Usage: ``python crash_writer.py points|maps DATA_DIR START KILL_AT``. It prints ``ready`` once
the store is open, then after each committed write the index of that write, one per line,
flushed. The expected content of write ``i`` is a pure function of ``i`` (below), so the test
can tell a whole write from a torn one.

With ``KILL_AT > 0`` the writer SIGKILLs itself just before its ``KILL_AT``-th step, a step
being one SQL statement (``BEGIN``, an ``INSERT``, ``COMMIT``, ...), one atomic file write of a
map (the picture, then the YAML) or the removal of a replaced map's files: a kill at every
boundary inside a write, chosen without any clock. With ``KILL_AT = 0`` the test kills it.
"""

from __future__ import annotations

import os
import signal
import sys
from typing import Any

import numpy as np

from polynav.geometry import Pose2D
from polynav.maps import ros_map
from polynav.maps.keepout import CircleZone
from polynav.maps.map import Map, MapInfo
from polynav.site import Point, PointKind
from polynav.store import SiteStore, map_tables

MAP = "lab"
KINDS = tuple(PointKind)
KEEPOUTS_PER_WRITE = 6


def point(i: int) -> Point:
    """The i-th point the writer adds."""
    pose = Pose2D(0.5 * i, -0.25 * i, 0.01 * i)
    return Point(f"p{i:05d}", MAP, pose, KINDS[i % len(KINDS)], None if i % 3 == 0 else i)


def keepouts(i: int) -> list[CircleZone]:
    """The keepouts the writer sets after adding point i (all rows of one write share i)."""
    return [CircleZone(float(i), float(j), 0.5 + j) for j in range(KEEPOUTS_PER_WRITE)]


def grid(v: int) -> Map:
    """Version v of the map the writer saves: size, origin and values all change with v."""
    rng = np.random.default_rng(v)
    h, w = 20 + v % 7, 30 + v % 5
    if v % 2:
        data = rng.integers(0, 101, size=(h, w)).astype(np.int8)  # scale mode
    else:
        data = rng.choice(np.array([0, 100, -1], dtype=np.int8), size=(h, w))  # trinary
    info = MapInfo(resolution=0.05 * (1 + v % 3), width=w, height=h, origin=Pose2D(v, -v, 0.0))
    return Map(info, data)


class _Steps:
    """Counts the writer's steps and kills the process before step ``kill_at``."""

    def __init__(self, kill_at: int) -> None:
        self.kill_at = kill_at
        self.count = 0

    def step(self) -> None:
        self.count += 1
        if self.count == self.kill_at:
            os.kill(os.getpid(), signal.SIGKILL)


class _CountingConnection:
    """A sqlite3 connection whose every statement is a step."""

    def __init__(self, conn: Any, steps: _Steps) -> None:
        self._conn = conn
        self._steps = steps

    def execute(self, *args: Any) -> Any:
        self._steps.step()
        return self._conn.execute(*args)

    def executemany(self, *args: Any) -> Any:
        self._steps.step()
        return self._conn.executemany(*args)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._conn, name)


def _instrument(store: SiteStore, steps: _Steps) -> None:
    store._conn = _CountingConnection(store._conn, steps)  # type: ignore[assignment]
    write_atomic = ros_map._write_atomic
    remove_files = store._remove_map_files

    def counted_write(*args: Any) -> None:
        steps.step()
        write_atomic(*args)

    def counted_remove(*args: Any) -> None:
        steps.step()
        remove_files(*args)

    ros_map._write_atomic = counted_write  # type: ignore[assignment]
    store._remove_map_files = counted_remove  # type: ignore[method-assign]
    assert map_tables.ros_map is ros_map


def main(mode: str, data_dir: str, start: int, kill_at: int) -> None:
    store = SiteStore.open(data_dir)
    if kill_at > 0:
        _instrument(store, _Steps(kill_at))
    print("ready", flush=True)
    i = start
    while True:
        if mode == "points":
            store.add_point(point(i))
            store.set_keepouts(MAP, keepouts(i))
        else:
            store.save_map(MAP, grid(i))
        print(i, flush=True)
        i += 1


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
