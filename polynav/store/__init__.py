"""The site store: floors, maps, points, keepouts, routes, connections and settings on disk.

One data directory per robot (DESIGN §6): ROS map files and an SQLite database, written so that
a crash at any moment leaves the previous state or the new one. Open it with
:meth:`SiteStore.open`.
"""

from __future__ import annotations

from polynav.store.records import (
    AutomationRecord,
    ConnectionRecord,
    FloorRecord,
    MapRecord,
    RouteRecord,
    ScheduleRecord,
    TaskRecord,
)
from polynav.store.site_store import SiteStore

__all__ = ["AutomationRecord", "ConnectionRecord", "FloorRecord", "MapRecord", "RouteRecord",
           "ScheduleRecord", "SiteStore", "TaskRecord"]
