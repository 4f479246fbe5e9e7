"""What "changes nothing" means in the Galileo suite: a digest of everything a request could
change, taken before and after a refused request and compared.

The digest holds the robot (mode, navigation state and attempt, map, IO outputs), the site store
(maps, floors, points, keepouts and routes of every map, connections, settings), the robot's
tasks, and the data directory's files with their sizes (uploads, voice records, photos, config
files; the store's database files are read through the store instead, as SQLite writes them on
reads too).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from polynav.protocols.galileo.server import GalileoServer
from polynav.runtime.robot_runtime import RobotRuntime

#: Files of the data directory that change without any request (the store's database).
VOLATILE = ("site.db",)


def files(root: Path) -> dict[str, int]:
    """Relative path -> size of every file under ``root`` (symlinks are not followed)."""
    out: dict[str, int] = {}
    for path in sorted(root.rglob("*")):
        name = path.relative_to(root).as_posix()
        if name.startswith(VOLATILE) or not path.is_file() or path.is_symlink():
            continue
        out[name] = path.stat().st_size
    return out


def digest(runtime: RobotRuntime, server: GalileoServer) -> dict[str, Any]:
    """Everything a request could change, in comparable form."""
    snap = runtime.status()
    store = runtime.store
    maps = [m.name for m in store.maps()]
    outputs = {bank: runtime.peripherals.io_state(bank)[0]
               for bank in ("io", "expansion_io", "voice_io")}
    return {
        "robot": (snap.mode, snap.navigation_state, snap.attempt_id, snap.map, snap.floor),
        "io": outputs,
        "maps": store.maps(),
        "floors": store.floors(),
        "points": store.points(),
        "keepouts": {name: store.keepouts(name) for name in maps},
        "routes": {name: store.routes(name) for name in maps},
        "connections": store.connections(),
        "settings": store.settings(),
        "tasks": runtime.tasks.list(),
        "files": files(server.ctx.data_dir),
    }
