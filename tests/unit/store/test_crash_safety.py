"""SIGKILL a process writing to the store at random moments; the store must never be torn.

The writer (``crash_writer.py``) reports each committed write on its stdout. Half the kills are
injected: the writer kills itself before a step chosen by a seeded RNG (a step is one SQL
statement, one atomic file write or one removal of old map files), so kills land at every
boundary inside a write, deterministically. The other half are external: the test reads until a
randomly chosen number of writes has been reported, then kills the writer wherever it is (inside
SQLite's commit, say). Reading the pipe paces the test; nothing sleeps.
"""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
from pathlib import Path

import numpy as np

from polynav.store import MapRecord, SiteStore
from tests.unit.store import crash_writer
from tests.unit.store.grids import assert_maps_equal

WRITER = Path(crash_writer.__file__)
# Steps of one write in the writer. A point write: BEGIN, SELECT map, SELECT point, INSERT,
# COMMIT, then for the keepouts BEGIN, SELECT map, DELETE, INSERT many, COMMIT.
POINT_STEPS = 10
# A map save: BEGIN, SELECT old row, SELECT serial, UPDATE serial, picture, YAML, INSERT, COMMIT,
# remove the old files, then BEGIN, SELECT, COMMIT to return the record.
MAP_STEPS = 12
EXTERNAL_KILLS = 8


def _kill_plan(rng: np.random.Generator, steps: int) -> list[tuple[int, int]]:
    """(writes to wait for, step to kill at or 0): every step of a write once, in a seeded
    order and after 0 to 2 whole writes, mixed with external kills after 0 to 5 writes."""
    injected = [(0, int(p) + steps * int(rng.integers(0, 3))) for p in rng.permutation(steps) + 1]
    external = [(int(rng.integers(0, 6)), 0) for _ in range(EXTERNAL_KILLS)]
    plan = injected + external
    return [plan[i] for i in rng.permutation(len(plan))]


def _run_and_kill(data: Path, mode: str, start: int, writes: int, kill_at: int = 0) -> int:
    """Run the writer until it is killed; the index of the last write it reported.

    With ``kill_at`` > 0 the writer kills itself before that step; else the test kills it
    after ``writes`` reported writes.
    """
    proc = subprocess.Popen(
        [sys.executable, str(WRITER), mode, str(data), str(start), str(kill_at)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert proc.stdout is not None
    try:
        assert proc.stdout.readline() == b"ready\n", proc.stderr.read() if proc.stderr else ""
        last = start - 1
        if kill_at > 0:
            last = max([last, *(int(line) for line in proc.stdout)])
        else:
            for _ in range(writes):
                line = proc.stdout.readline()
                assert line, proc.stderr.read() if proc.stderr else ""
                last = int(line)
            os.kill(proc.pid, signal.SIGKILL)
            # The writer may have gone on writing before the kill landed (a loaded machine
            # can pause this process for many writes): what it reported is in the pipe.
            last = max([last, *(int(line) for line in proc.stdout)])
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.wait()
        proc.stdout.close()
        if proc.stderr is not None:
            proc.stderr.close()
    assert proc.returncode == -signal.SIGKILL
    return last


def _integrity(db: Path) -> str:
    conn = sqlite3.connect(str(db))
    try:
        return str(conn.execute("PRAGMA integrity_check").fetchone()[0])
    finally:
        conn.close()


def test_points_and_keepouts_stay_whole_when_the_writer_is_killed(tmp_path: Path) -> None:
    data = tmp_path / "data"
    with SiteStore.open(data) as store:
        store.save_map(crash_writer.MAP, crash_writer.grid(0))
    rng = np.random.default_rng(20261123)
    count = 0
    zones_of = -1
    for writes, kill_at in _kill_plan(rng, POINT_STEPS):
        start = count
        last = _run_and_kill(data, "points", start, writes, kill_at)
        assert _integrity(data / "site.db") == "ok"
        with SiteStore.open(data) as store:
            points = store.points(map_name=crash_writer.MAP)
            zones = store.keepouts(crash_writer.MAP)
        count = len(points)
        # Every reported write is there, at most one more got in before the kill.
        assert last + 1 <= count <= last + 2
        assert points == [crash_writer.point(i) for i in range(count)]
        # The keepouts are all of one write: the last reported one or a later one (a kill
        # between adding a point and replacing the keepouts leaves the previous keepouts).
        if not zones:  # none set yet
            assert (zones_of, last) == (-1, -1)
            continue
        done = max(last, zones_of) if last >= start else zones_of
        matches = [j for j in range(done, count) if zones == crash_writer.keepouts(j)]
        assert matches, (done, count, zones)
        zones_of = matches[0]
    assert count >= POINT_STEPS


def test_map_is_always_one_saved_version_when_the_writer_is_killed(tmp_path: Path) -> None:
    data = tmp_path / "data"
    with SiteStore.open(data) as store:
        store.save_map(crash_writer.MAP, crash_writer.grid(0))
    rng = np.random.default_rng(7)
    version = 0
    for writes, kill_at in _kill_plan(rng, MAP_STEPS):
        last = _run_and_kill(data, "maps", version + 1, writes, kill_at)
        assert _integrity(data / "site.db") == "ok"
        with SiteStore.open(data) as store:
            loaded = store.load_map(crash_writer.MAP)
            record = store.map_record(crash_writer.MAP)
            files = sorted(p.name for p in (data / "maps").iterdir())
        candidates = [v for v in (last, last + 1) if loaded.info == crash_writer.grid(v).info]
        assert len(candidates) == 1, (last, loaded.info)
        version = candidates[0]
        assert version >= last
        expected = crash_writer.grid(version)
        assert_maps_equal(loaded, expected)
        info = expected.info
        assert record == MapRecord(
            crash_writer.MAP, None, info.resolution, info.width, info.height, info.origin
        )
        # Leftovers of the killed save were removed on open: one YAML and its picture remain.
        assert len(files) == 2
        assert files[0].endswith(".png") and files[1] == files[0][:-4] + ".yaml"
