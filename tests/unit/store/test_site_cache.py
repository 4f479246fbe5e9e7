"""Hot reads of the site store come from memory; every write, ours or another process's, is
seen at once (issue 19: status paths never touch the disk)."""

from __future__ import annotations

import sqlite3

import pytest

from polynav.errors import Conflict, NotFound
from polynav.geometry import Pose2D
from polynav.site import Point, PointKind
from polynav.store import FloorRecord, SiteStore

PARCEL = Point("parcel", "floor1", Pose2D(6.0, 12.0, 0.0), PointKind.GENERAL, None)


def _statements(store: SiteStore) -> list[str]:
    seen: list[str] = []
    conn = store._conn
    assert isinstance(conn, sqlite3.Connection)
    conn.set_trace_callback(seen.append)
    return seen


def test_a_warm_floor_points_and_count_read_runs_no_query_but_data_version(
    demo_store: SiteStore,
) -> None:
    demo_store.floor("floor1")
    demo_store.points(map_name="floor1")
    demo_store.count_points(map_name="floor1")
    seen = _statements(demo_store)
    for _ in range(100):
        assert demo_store.floor("floor1").level == 1
        assert len(demo_store.points(map_name="floor1")) == demo_store.count_points(
            map_name="floor1")
    assert set(seen) == {"PRAGMA data_version"}


def test_count_points_counts_in_the_database(demo_store: SiteStore) -> None:
    seen = _statements(demo_store)
    count = demo_store.count_points(map_name="floor1")
    assert count == len(demo_store.points(map_name="floor1")) > 0
    assert any("COUNT(*)" in s for s in seen)
    with pytest.raises(NotFound):
        demo_store.count_points(map_name="nowhere")


def test_our_own_write_is_seen_by_the_next_read(demo_store: SiteStore) -> None:
    before = demo_store.count_points(map_name="floor1")
    names = [p.name for p in demo_store.points(map_name="floor1")]
    demo_store.add_point(PARCEL)
    assert demo_store.count_points(map_name="floor1") == before + 1
    assert [p.name for p in demo_store.points(map_name="floor1")] == [*names, "parcel"]
    demo_store.delete_point("floor1", "parcel")
    assert demo_store.count_points(map_name="floor1") == before


def test_another_processs_commit_is_seen_by_the_next_read(demo_store: SiteStore) -> None:
    before = demo_store.count_points(map_name="floor1")
    assert demo_store.floor("floor1") == FloorRecord("floor1", 1, "floor1")
    with SiteStore.open(demo_store.data_dir) as other:  # a second connection: `polynav points`
        other.add_point(PARCEL)
        other.save_floor(FloorRecord("floor1", 7, "floor1"))
    assert demo_store.count_points(map_name="floor1") == before + 1
    assert demo_store.floor("floor1").level == 7


def test_a_failed_write_leaves_the_cache_consistent(demo_store: SiteStore) -> None:
    demo_store.add_point(PARCEL)
    count = demo_store.count_points(map_name="floor1")
    with pytest.raises(Conflict):
        demo_store.add_point(PARCEL)
    assert demo_store.count_points(map_name="floor1") == count
