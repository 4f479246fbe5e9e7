"""The whole Yunji command table: path -> handler, from each group's module."""

from __future__ import annotations

from polynav.protocols.yunji import commands, device, queries, streams
from polynav.protocols.yunji.commands import Handler

HANDLERS: dict[str, Handler] = {
    **commands.HANDLERS,
    **streams.HANDLERS,
    **device.HANDLERS,
    **queries.HANDLERS,
}
