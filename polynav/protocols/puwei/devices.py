"""``GET /api/devices`` (puwei-api §3.2): the LAN's Puwei devices, asked of one known device.

polynav serves one robot, so the list is this robot's own address: the one the server is bound
to (loopback by default; :mod:`~polynav.protocols.puwei.server` records it), never a guess at
other interfaces. Public,
as the document lists no ``authorization`` header for it (A4).
"""

from __future__ import annotations

from polynav.protocols.puwei.context import Context
from polynav.protocols.puwei.endpoint import RouteList
from polynav.protocols.puwei.request import PuweiRequest

ROUTES = RouteList()


@ROUTES.get("/api/devices", inline=True, public=True)
def devices(ctx: Context, request: PuweiRequest) -> list[str]:
    """``data``: the IP strings of the devices (this one)."""
    address = ctx.state("puwei.address", lambda: "127.0.0.1")
    return [address]
