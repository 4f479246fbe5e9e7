"""Paths and target points of a map (galileo-http-b §7–8, E38–E45).

A Galileo path is a polynav route with stops (:mod:`polynav.store.route_stops`): the path file
is the route's drawn polyline, kept as uploaded; the target points are its stops, each a named
point of the map, so they are the same points the native API and the other dialects see.
Every map has the path ``default``, whose target points are the map's named points other than
chargers (the charge pile is index -1), in the store's order; its path file is the list of
those points. Missing ``map_name``/``path_name`` of the target-point endpoints mean the map and
path in use (doc 4349, 4389).
"""

from __future__ import annotations

import logging
from typing import Any

from polynav.protocols.galileo import convert
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.store.route_stops import StopRoute

log = logging.getLogger(__name__)

ROUTES = RouteList()


def path_text(ctx: Context, route: StopRoute) -> str:
    """The path file: as uploaded, else the polyline drawn (the web console's), else the stops'
    positions (the synthesized default path)."""
    if route.polyline_text is not None:
        return route.polyline_text
    if route.polyline:
        return convert.format_path(route.polyline)
    points = sessions.routes(ctx).stop_points(route)
    return convert.format_path((p.pose.x, p.pose.y, s.z) for p, s in zip(points, route.stops,
                                                                         strict=True))


def targets_text(ctx: Context, route: StopRoute) -> str:
    points = sessions.routes(ctx).stop_points(route)
    return "".join(
        convert.target_line(p.pose, s.z, s.error_x, s.error_y, s.direction, s.label)
        for p, s in zip(points, route.stops, strict=True)
    )


@ROUTES.get("/navigation/path")
def get_path(ctx: Context, params: Params) -> Reply:
    """E38: one path file, one map's path names, or every map's."""
    map_name = params.text("map_name", None)
    path_name = params.text("path_name", None)
    book = sessions.routes(ctx)
    if map_name is None:
        return {m.name: book.names(m.name) for m in ctx.store.maps()}
    if path_name is None:
        return book.names(map_name)
    route = book.route(map_name, path_name)
    return {"map_name": map_name, "path_name": path_name, "path_data": path_text(ctx, route)}


def _put_path(ctx: Context, params: Params) -> dict[str, Any]:
    map_name, path_name = params.text("map_name"), params.text("path_name")
    text = params.text("path_data")
    polyline = convert.parse_path(text)
    sessions.routes(ctx).save_polyline(map_name, path_name, polyline, text)
    return {"map_name": map_name, "path_name": path_name, "path_data": text}


@ROUTES.post("/navigation/path")
def post_path(ctx: Context, params: Params) -> Reply:
    """E39: create or overwrite a path file; the reply echoes the request."""
    return _put_path(ctx, params)


@ROUTES.put("/navigation/path")
def put_path(ctx: Context, params: Params) -> Reply:
    """E40: as E39."""
    return _put_path(ctx, params)


@ROUTES.delete("/navigation/path")
def delete_path(ctx: Context, params: Params) -> Reply:
    """E41: the path, its target points, ignore areas and virtual walls."""
    sessions.routes(ctx).delete(params.text("map_name"), params.text("path_name"))
    return {"status": "ok"}


def _map_and_path(ctx: Context, params: Params) -> tuple[str, str]:
    map_name = params.text("map_name", None) or sessions.current_map(ctx)
    path_name = params.text("path_name", None) or sessions.current_path(ctx, map_name)
    return map_name, path_name


@ROUTES.get("/navigation/nav_points")
def get_nav_points(ctx: Context, params: Params) -> Reply:
    """E42: the target-point file of (map, path), by default the ones in use."""
    map_name, path_name = _map_and_path(ctx, params)
    route = sessions.routes(ctx).route(map_name, path_name)
    return {"map_name": map_name, "path_name": path_name,
            "path_data": targets_text(ctx, route)}


def _put_nav_points(ctx: Context, params: Params) -> dict[str, Any]:
    text = params.text("path_data")
    stops = convert.parse_targets(text)
    map_name, path_name = _map_and_path(ctx, params)
    sessions.routes(ctx).set_stops(map_name, path_name, stops)
    return {"map_name": map_name, "path_name": path_name, "path_data": text}


@ROUTES.post("/navigation/nav_points")
def post_nav_points(ctx: Context, params: Params) -> Reply:
    """E43: replace the target points of (map, path); the reply echoes the request."""
    return _put_nav_points(ctx, params)


@ROUTES.put("/navigation/nav_points")
def put_nav_points(ctx: Context, params: Params) -> Reply:
    """E44: as E43."""
    return _put_nav_points(ctx, params)


@ROUTES.delete("/navigation/nav_points")
def delete_nav_points(ctx: Context, params: Params) -> Reply:
    """E45: the target points go, the path stays."""
    sessions.routes(ctx).clear_stops(params.text("map_name"), params.text("path_name"))
    return {"status": "ok"}
