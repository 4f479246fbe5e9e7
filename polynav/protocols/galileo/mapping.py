"""The mapping endpoints (galileo-http-b §3, E1–E8) on the runtime's mapping mode.

``map/start`` starts a new map where the robot stands (runtime ``start_mapping``); the robot is
then driven by remote control (``PUT /system/speed`` or WebSocket ``/cmd_vel``).
``POST map/current_map_image`` saves the map so far under a name (mapping goes on) with its
``type`` and ``levels``; ``map/stop`` saves once more and stops (doc: it saves automatically),
under the name last saved, else under ``slamdb`` (the vendor's working-map folder name).
``map/track`` is the scan poses of the map last saved. ``map/update`` extends a saved map in its
own frame (its points, paths and zones stay valid) and ``map/stop`` saves it back under its name.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

from starlette.responses import Response

from polynav.errors import Conflict
from polynav.maps import ros_map
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.map_meta import MapMeta, MapMetaBook, check_meta
from polynav.protocols.galileo.params import Params

log = logging.getLogger(__name__)

ROUTES = RouteList()

WORKING_MAP = "slamdb"


@dataclass
class MappingState:
    """The name the map being built was last saved under, and its metadata."""

    saved_as: str | None = None
    meta: MapMeta | None = None


def metas(ctx: Context) -> MapMetaBook:
    return ctx.state("map_meta", lambda: MapMetaBook(ctx.store,
                                                     ctx.data_dir / "galileo" / "maps.json"))


def _state(ctx: Context) -> MappingState:
    return ctx.state("mapping", MappingState)


def saving_name(ctx: Context) -> str:
    """The name the map being built is saved under: the last name it was saved as, else
    ``slamdb``."""
    return _state(ctx).saved_as or WORKING_MAP


def _track(ctx: Context) -> tuple[tuple[float, float, float], ...]:
    return tuple((p.x, p.y, 0.0) for p in ctx.runtime.mapping_trajectory())


@ROUTES.get("/map/start", result_errors=True)
def map_start(ctx: Context, params: Params) -> Reply:
    """E1: ``camera_id`` is accepted (polynav maps with the lidar)."""
    params.integer("camera_id", None)
    ctx.runtime.start_mapping()
    state = _state(ctx)
    state.saved_as, state.meta = None, None
    return {"result": True}


@ROUTES.get("/map/stop", result_errors=True)
def map_stop(ctx: Context, params: Params) -> Reply:
    """E2: save (under the last saved name, else ``slamdb``) and stop."""
    state = _state(ctx)
    name = saving_name(ctx)
    track = _track(ctx)
    ctx.runtime.stop_mapping(name, overwrite=True)
    meta = state.meta or metas(ctx).get(name)
    metas(ctx).put(name, MapMeta(meta.levels, meta.map_type, track))
    state.saved_as, state.meta = None, None
    return {"result": True}


@ROUTES.get("/map/update", result_errors=True)
def map_update(ctx: Context, params: Params) -> Reply:
    """E3: mapping on top of a saved map (A-3), kept in its frame, saved back under its name.

    ``map`` defaults to the map of the last navigation; ``path`` + ``start_index`` name the
    target point the robot stands on. Without ``start_index`` polynav finds the robot itself
    (navigation's estimate when navigating on that map, else global relocalization), as
    ``navigation/start`` does.
    """
    name = params.text("map", None) or sessions.current_map(ctx)
    ctx.store.map_record(name)  # NotFound before anything changes
    path = params.text("path", None) or sessions.current_path(ctx, name)
    _, point = sessions.start_point(ctx, params, name, path)
    ctx.runtime.start_mapping(name, point=point)
    state = _state(ctx)
    state.saved_as, state.meta = name, metas(ctx).get(name)
    log.info("galileo: updating map %s from %s", name, point or "where the robot is found")
    return {"result": True}


@ROUTES.get("/map/pose")
def map_pose(ctx: Context, params: Params) -> Reply:
    """E4: the pose on the map being built, ``angle`` in degrees."""
    if ctx.runtime.status().mode != "mapping":
        raise Conflict("not mapping: start mapping first")
    pose = ctx.runtime.status().pose
    return {"x": float(pose.x), "y": float(pose.y), "angle": math.degrees(pose.theta)}


@ROUTES.get("/map/current_map_image")
def get_current_map_image(ctx: Context, params: Params) -> Reply:
    """E5: the live map's parameters and the URL of its picture."""
    info = ctx.runtime.mapping_map().info
    return {
        "status": "OK",
        "map_params": {"origin": [info.origin.x, info.origin.y, info.origin.theta],
                       "width": info.width, "resolution": info.resolution,
                       "height": info.height},
        "map_image": "/api/v1/map/current_map_png",
    }


@ROUTES.post("/map/current_map_image", result_errors=True)
def save_current_map_image(ctx: Context, params: Params) -> Reply:
    """E6: save the map so far as ``name`` (replacing a map of that name)."""
    name = params.text("name")
    map_type, levels = check_meta(params.text("type", "floor"), params.raw("levels", [1]))
    track = _track(ctx)
    ctx.runtime.save_mapping(name, overwrite=True)
    meta = MapMeta(levels, map_type, track)
    metas(ctx).put(name, meta)
    state = _state(ctx)
    state.saved_as, state.meta = name, meta
    return {"result": True, "name": name}


@ROUTES.get("/map/current_map_png")
def current_map_png(ctx: Context, params: Params) -> Reply:
    """E7."""
    return Response(ros_map.png_bytes(ctx.runtime.mapping_map()), media_type="image/png")


@ROUTES.get("/map/track")
def map_track(ctx: Context, params: Params) -> Reply:
    """E8: the trajectory of the map last saved in this mapping session (``[]`` before)."""
    state = _state(ctx)
    if state.saved_as is None:
        return {"trajectory": []}
    track = metas(ctx).get(state.saved_as).track
    return {"trajectory": [{"x": x, "y": y, "z": z} for x, y, z in track]}
