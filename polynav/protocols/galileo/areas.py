"""Ignore areas and virtual walls of a (map, path) (galileo-http-b §10, E50–E55).

They are stored with the path (:mod:`polynav.store.route_stops`) and mirrored into the map's
keepouts, so the costmap keeps the robot out of them the next time navigation starts or
reloads the map, and the native API lists them. Following DESIGN §2, an ignore area is a
forbidden zone (the spec's A-6 leaves its meaning open); virtual-wall points become wall
polylines (points further apart than 0.3 m start a new wall).
"""

from __future__ import annotations

from polynav.protocols.galileo import convert
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params

ROUTES = RouteList()


def _names(params: Params) -> tuple[str, str]:
    return params.text("map_name"), params.text("path_name")


@ROUTES.get("/navigation/skip_area")
def get_skip_area(ctx: Context, params: Params) -> Reply:
    """E50."""
    map_name, path_name = _names(params)
    route = sessions.routes(ctx).route(map_name, path_name)
    return {"map_name": map_name, "path_name": path_name,
            "skip_area": convert.format_areas(route.areas)}


@ROUTES.post("/navigation/skip_area")
def post_skip_area(ctx: Context, params: Params) -> Reply:
    """E51: replace the areas; the reply echoes the request."""
    map_name, path_name = _names(params)
    text = params.text("skip_area")
    sessions.routes(ctx).set_areas(map_name, path_name, convert.parse_areas(text))
    return {"map_name": map_name, "path_name": path_name, "skip_area": text}


@ROUTES.delete("/navigation/skip_area")
def delete_skip_area(ctx: Context, params: Params) -> Reply:
    """E52."""
    map_name, path_name = _names(params)
    sessions.routes(ctx).route(map_name, path_name)
    sessions.routes(ctx).set_areas(map_name, path_name, [])
    return {"status": "ok"}


@ROUTES.get("/navigation/virtual_wall")
def get_virtual_wall(ctx: Context, params: Params) -> Reply:
    """E53."""
    map_name, path_name = _names(params)
    route = sessions.routes(ctx).route(map_name, path_name)
    return {"map_name": map_name, "path_name": path_name,
            "virtual_wall": convert.format_walls(route.walls)}


@ROUTES.post("/navigation/virtual_wall")
def post_virtual_wall(ctx: Context, params: Params) -> Reply:
    """E54: replace the wall points; the reply echoes the request."""
    map_name, path_name = _names(params)
    text = params.text("virtual_wall")
    sessions.routes(ctx).set_walls(map_name, path_name, convert.parse_walls(text))
    return {"map_name": map_name, "path_name": path_name, "virtual_wall": text}


@ROUTES.delete("/navigation/virtual_wall")
def delete_virtual_wall(ctx: Context, params: Params) -> Reply:
    """E55."""
    map_name, path_name = _names(params)
    sessions.routes(ctx).route(map_name, path_name)
    sessions.routes(ctx).set_walls(map_name, path_name, [])
    return {"status": "ok"}
