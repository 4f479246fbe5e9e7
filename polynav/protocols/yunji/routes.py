"""The whole Yunji command table: path -> handler, from each group's module."""

from __future__ import annotations

from polynav.protocols.yunji import device, maps, markers, moves, queries, robot, streams
from polynav.protocols.yunji.context import Handler

HANDLERS: dict[str, Handler] = {
    **robot.HANDLERS,
    **moves.HANDLERS,
    **markers.HANDLERS,
    **maps.HANDLERS,
    **streams.HANDLERS,
    **device.HANDLERS,
    **queries.HANDLERS,
}

# Commands that only read the runtime's snapshot and the store's in-memory cache: answered on
# the server's loop instead of a worker thread (a thread hop costs more than the answer).
SNAPSHOT_READS: frozenset[str] = frozenset({
    "/api/robot_status", "/api/robot_info", "/api/software/get_version", "/api/get_params",
})
