"""The wind sensor and QR-code landmarks (galileo-http-b E63, E64).

polynav's robots carry no wind sensor and its maps hold no QR-code landmarks, so the answers
say so in the documented shapes: every wind field ``-1`` (the spec's "no sensor" reading), and
an empty landmark list per map. An unknown map is 404.
"""

from __future__ import annotations

from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params

ROUTES = RouteList()


@ROUTES.get("/navigation/wind_info", inline=True)
def wind_info(ctx: Context, params: Params) -> Reply:
    """E63: no wind sensor: ``-1`` everywhere."""
    return {"current_speed": -1.0, "max_speed": -1.0, "level": -1.0, "direction": -1.0}


@ROUTES.get("/navigation/landmarks")
def landmarks(ctx: Context, params: Params) -> Reply:
    """E64: one map's landmarks, or every map's in an array."""
    name = params.text("map_name", None)
    if name is not None:
        ctx.store.map_record(name)
        return {"map_name": name, "landmarks": []}
    return [{"map_name": m.name, "landmarks": []} for m in ctx.store.maps()]
