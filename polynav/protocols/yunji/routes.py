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
