"""Yunji map commands (§3.14.1-§3.14.4): maps and the floors they belong to, the current map
and switching it."""

from __future__ import annotations

from polynav.errors import Conflict, InvalidRequest
from polynav.protocols.yunji.context import (
    Context,
    Handler,
    Params,
    current_map,
    floor_level,
    move_status_of,
    optional_int,
)
from polynav.protocols.yunji.messages import MoveStatus, Reply


def map_list(ctx: Context, params: Params) -> Reply:
    """§3.14.1: ``map name -> [floors]``; in polynav a map belongs to one floor at most."""
    levels = {f.name: f.level for f in ctx.store.floors()}
    return Reply(
        results={
            m.name: ([levels[m.floor]] if m.floor in levels else []) for m in ctx.store.maps()
        }
    )


def map_list_info(ctx: Context, params: Params) -> Reply:
    """§3.14.4: ``map name -> [{floor, resolution, height, width, origin_x, origin_y}]``."""
    levels = {f.name: f.level for f in ctx.store.floors()}
    results: dict[str, object] = {}
    for m in ctx.store.maps():
        results[m.name] = [
            {
                "floor": levels[m.floor],
                "resolution": m.resolution,
                "height": m.height,
                "width": m.width,
                "origin_x": m.origin.x,
                "origin_y": m.origin.y,
            }
        ] if m.floor in levels else []
    return Reply(results=results)


def map_set_current_map(ctx: Context, params: Params) -> Reply:
    """§3.14.2: navigate on ``map_name`` (or the deprecated ``hotel_id``, §A-P3) at ``floor``,
    which must be that map's floor. Refused while a move runs, as a move is."""
    name = params.get("map_name") or params.get("hotel_id")
    if not name:
        raise InvalidRequest("map_name", "is required")
    level = optional_int(params, "floor")
    if level is None:
        raise InvalidRequest("floor", "is required")
    record = ctx.store.map_record(name)
    levels = {f.name: f.level for f in ctx.store.floors()}
    if record.floor not in levels or levels[record.floor] != level:
        raise InvalidRequest("floor", f"map {name!r} is not on floor {level}")
    if move_status_of(ctx.runtime.status()) is MoveStatus.RUNNING:
        raise Conflict("a move task is running: cancel it first")
    ctx.runtime.start_navigation(name)
    return Reply()


def map_get_current_map(ctx: Context, params: Params) -> Reply:
    """§3.14.3: ``floor`` is a string as in the spec's example (§A-J4)."""
    s = ctx.runtime.status()
    record = ctx.store.map_record(current_map(ctx))
    return Reply(
        results={
            "hotel_id": record.name,
            "map_name": record.name,
            "floor": str(floor_level(ctx, s.floor)),
            "info": {
                "resolution": record.resolution,
                "width": record.width,
                "height": record.height,
                "origin_x": record.origin.x,
                "origin_y": record.origin.y,
            },
        }
    )


HANDLERS: dict[str, Handler] = {
    "/api/map/list": map_list,
    "/api/map/list_info": map_list_info,
    "/api/map/set_current_map": map_set_current_map,
    "/api/map/get_current_map": map_get_current_map,
}
