"""The site store: floors, maps, points, keepouts, routes, connections and settings on disk.

One data directory per robot (DESIGN §6): ROS map files and an SQLite database, written so that
a crash at any moment leaves the previous state or the new one. Open it with
:meth:`SiteStore.open`.
"""

from __future__ import annotations

from polynav.store.records import ConnectionRecord, FloorRecord, MapRecord, RouteRecord
from polynav.store.site_store import SiteStore

__all__ = ["ConnectionRecord", "FloorRecord", "MapRecord", "RouteRecord", "SiteStore"]
