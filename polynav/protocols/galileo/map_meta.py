"""What Galileo says about a map beyond the ROS map files: ``levels``, ``map_type`` and the
mapping trajectory (galileo-http-b §1.3).

Kept per map name in ``<data>/galileo/maps.json``, written atomically (temp file, fsync,
rename), beside the vendor-format ``config.json``: these are the dialect's words, not the site's.
A map without an entry reads as a floor map on the level of the floor it belongs to (``[1]``
for a map on no floor), with no trajectory.
"""

from __future__ import annotations

import json
import logging
import os
import tempfile
import threading
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from polynav.errors import InvalidRequest, StorageError
from polynav.store.site_store import SiteStore

log = logging.getLogger(__name__)

MAP_TYPES = ("floor", "elevator")
Track = tuple[tuple[float, float, float], ...]


@dataclass(frozen=True, slots=True)
class MapMeta:
    levels: tuple[int, ...]
    map_type: str = "floor"
    track: Track = ()


def check_meta(map_type: str, levels: object) -> tuple[str, tuple[int, ...]]:
    """A valid (map_type, levels) pair, else InvalidRequest naming the field. ``levels`` may
    be one integer, a list, or either as JSON text (a query string)."""
    if isinstance(levels, str):
        try:
            levels = json.loads(levels)
        except ValueError:
            raise InvalidRequest("levels", f"must be a list of integers, got {levels!r}") from None
    if map_type not in MAP_TYPES:
        raise InvalidRequest("type", f"must be 'floor' or 'elevator', got {map_type!r}")
    if isinstance(levels, int) and not isinstance(levels, bool):
        levels = [levels]
    if not isinstance(levels, list) or not levels or not all(
        isinstance(v, int) and not isinstance(v, bool) for v in levels
    ):
        raise InvalidRequest("levels", f"must be a non-empty list of integers, got {levels!r}")
    return map_type, tuple(int(v) for v in levels)


@dataclass
class MapMetaBook:
    """The maps' Galileo metadata, backed by one JSON file."""

    store: SiteStore
    path: Path
    _lock: threading.Lock = field(default_factory=threading.Lock)

    def get(self, map_name: str) -> MapMeta:
        entry = self._read().get(map_name)
        if entry is None:
            return MapMeta(self._default_levels(map_name))
        return MapMeta(
            tuple(int(v) for v in entry.get("levels") or self._default_levels(map_name)),
            str(entry.get("map_type", "floor")),
            tuple((float(p[0]), float(p[1]), float(p[2])) for p in entry.get("track", ())),
        )

    def put(self, map_name: str, meta: MapMeta) -> None:
        with self._lock:
            data = self._read()
            data[map_name] = {"levels": list(meta.levels), "map_type": meta.map_type,
                              "track": [list(p) for p in meta.track]}
            self._write(data)

    def forget(self, map_name: str) -> None:
        with self._lock:
            data = self._read()
            if data.pop(map_name, None) is not None:
                self._write(data)

    def _default_levels(self, map_name: str) -> tuple[int, ...]:
        record = self.store.map_record(map_name)
        if record.floor is not None:
            return (int(self.store.floor(record.floor).level),)
        return (1,)

    def _read(self) -> dict[str, Any]:
        try:
            data = json.loads(self.path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            return {}
        except (OSError, ValueError) as exc:
            raise StorageError(f"cannot read {self.path}: {exc}") from exc
        if not isinstance(data, dict):
            raise StorageError(f"{self.path} does not hold a JSON object")
        return data

    def _write(self, data: dict[str, Any]) -> None:
        folder = self.path.parent
        try:
            folder.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=".maps.", suffix=".tmp", dir=folder)
            with os.fdopen(fd, "w", encoding="utf-8") as handle:
                json.dump(data, handle, ensure_ascii=False)
                handle.flush()
                os.fsync(handle.fileno())
            os.replace(tmp, self.path)
        except OSError as exc:
            raise StorageError(f"cannot write {self.path}: {exc}") from exc
