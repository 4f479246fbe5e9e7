"""Saved maps, their pictures and archives (galileo-http-b §5, E18–E26).

* ``saved_maps``: every map of the site store, with the ROS map fields, ``md5sum`` (the md5 of
  the map's stored picture file, A-13), and ``map_type``/``levels`` from :mod:`.map_meta`; polynav
  builds lidar maps, so ``slam_type`` is ``lidar`` and ``type=camera`` lists none.
* ``map_pgm``/``map_png``: the picture in ROS ``map_saver`` form (binary PGM P5, or PNG).
* ``download_map_from_robot``: a zip holding ``map.yaml`` + ``map.png`` (ROS map_server files)
  and ``galileo.json`` (``map_type``, ``levels``, the trajectory, and every stored path with its
  path file, target points, ignore areas and virtual walls); ``upload_map_to_robot`` takes that
  archive back under ``map_name`` (A-14), replacing a map of that name. Only those three member
  names are read, each at most :data:`MAX_MEMBER` bytes, so an archive cannot write outside a
  temporary folder or fill the disk.
* ``upload_map``/``download_map`` exchange maps with a Lagrange dispatch server: a task of one
  ``upload_map_action``/``download_map_action`` (:mod:`polynav.tasks.actions.transfer`) on the
  dispatch servers polynav is configured with (``--dispatch-server ID=URL``); a server id it
  does not know ends the task in ``ERROR`` at once, with the reason in the action's ``result``.
  The robot runs one task at a time, so a transfer asked while a task runs is refused (409)
  rather than stopping that task.
"""

from __future__ import annotations

import hashlib
import io
import json
import logging
import tempfile
import zipfile
from pathlib import Path
from typing import Any

import yaml
from starlette.responses import Response

from polynav import safe_yaml
from polynav.errors import Conflict, InvalidRequest, PolynavError
from polynav.maps import ros_map
from polynav.protocols.galileo import convert
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo import task_objects as objects
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.map_meta import MapMeta, check_meta
from polynav.protocols.galileo.mapping import metas
from polynav.protocols.galileo.params import Params
from polynav.runtime.map_exchange import map_archive
from polynav.store.route_stops import StopInput

log = logging.getLogger(__name__)

ROUTES = RouteList()

MAX_MEMBER = 64 * 1024 * 1024  # [bytes] per archive member
OCCUPIED_THRESH = 0.65
FREE_THRESH = 0.196


def md5sum(ctx: Context, name: str) -> str:
    return hashlib.md5(ctx.store.map_image_path(name).read_bytes()).hexdigest()


def map_details(ctx: Context, name: str) -> dict[str, Any]:
    record = ctx.store.map_record(name)
    meta = metas(ctx).get(name)
    o = record.origin
    return {
        "resolution": record.resolution,
        "origin": [o.x, o.y, o.theta],
        "occupied_thresh": OCCUPIED_THRESH,
        "free_thresh": FREE_THRESH,
        "negate": 0,
        "name": name,
        "md5sum": md5sum(ctx, name),
        "map_type": meta.map_type,
        "levels": list(meta.levels),
        "slam_type": "lidar",
    }


@ROUTES.get("/navigation/saved_maps")
def saved_maps(ctx: Context, params: Params) -> Reply:
    """E18: an array of map objects (one or none with ``name``)."""
    kind = params.text("type", "all")
    if kind not in ("all", "lidar", "camera"):
        raise InvalidRequest("type", f"must be lidar, camera or all, got {kind!r}")
    if kind == "camera":
        return []
    name = params.text("name", None)
    names = [m.name for m in ctx.store.maps()]
    if name is not None:
        names = [n for n in names if n == name]
    return [map_details(ctx, n) for n in names]


def _track_points(track: Any) -> list[dict[str, float]]:
    return [{"x": x, "y": y, "z": z} for x, y, z in track]


@ROUTES.get("/navigation/robot_tracks")
def robot_tracks(ctx: Context, params: Params) -> Reply:
    """E19: one map's ``{"trajectory"}``, or ``[{"map_name", "track"}]`` for all (A-9)."""
    name = params.text("map_name", None)
    if name is not None:
        ctx.store.map_record(name)
        return {"trajectory": _track_points(metas(ctx).get(name).track)}
    return [{"map_name": m.name, "track": _track_points(metas(ctx).get(m.name).track)}
            for m in ctx.store.maps()]


def pgm_bytes(ctx: Context, name: str) -> bytes:
    grid = ctx.store.load_map(name)
    with tempfile.TemporaryDirectory() as folder:
        yaml_path = Path(folder) / "map.yaml"
        ros_map.save_map(grid, yaml_path, image_format="pgm")
        return (Path(folder) / "map.pgm").read_bytes()


@ROUTES.get("/navigation/map_pgm")
def map_pgm(ctx: Context, params: Params) -> Reply:
    """E20."""
    return Response(pgm_bytes(ctx, params.text("name")), media_type="image/x-portable-graymap")


@ROUTES.get("/navigation/map_png")
def map_png(ctx: Context, params: Params) -> Reply:
    """E21."""
    name = params.text("name")
    ctx.store.map_record(name)
    return Response(ctx.store.map_image_path(name).read_bytes(), media_type="image/png")


@ROUTES.get("/navigation/current_map")
def current_map(ctx: Context, params: Params) -> Reply:
    """E22."""
    name = sessions.current_map(ctx)
    return {"name": name, "md5sum": md5sum(ctx, name)}


def _transfer(ctx: Context, name: str, action: dict[str, Any]) -> Reply:
    """Run the transfer task ``name`` of ``action``; the task."""
    busy = ctx.runtime.tasks.running()
    if busy is not None:
        raise Conflict(f"task {busy['name']!r} is {busy['state']}: a map transfer runs alone")
    return objects.render(objects.create(ctx, {"name": name, "sub_tasks": [action]},
                                         kind=objects.TRANSFER, start=True))


@ROUTES.get("/navigation/upload_map")
def upload_map(ctx: Context, params: Params) -> Reply:
    """E23: the ``upload_map`` task: the map in use sent to ``server_id``."""
    return _transfer(ctx, "upload_map", {"type": "upload_map_action",
                                         "server_id": params.text("server_id")})


@ROUTES.get("/navigation/download_map")
def download_map(ctx: Context, params: Params) -> Reply:
    """E24: the ``download_map`` task: map ``map_id`` fetched from ``server_id``."""
    return _transfer(ctx, "download_map", {"type": "download_map_action",
                                           "server_id": params.text("server_id"),
                                           "map_id": params.text("map_id")})


def archive(ctx: Context, name: str) -> bytes:
    """The map archive of ``name`` (see the module docstring)."""
    grid = ctx.store.load_map(name)
    meta = metas(ctx).get(name)
    routes = sessions.routes(ctx)
    paths = []
    for path in routes.names(name):
        route = routes.route(name, path)
        if not route.stored:
            continue
        points = routes.stop_points(route)
        paths.append({
            "name": path,
            "path_data": route.polyline_text,
            "map_points": route.map_points,
            "nav_points": "".join(
                convert.target_line(p.pose, s.z, s.error_x, s.error_y, s.direction,
                                    s.label or p.name)
                for p, s in zip(points, route.stops, strict=True)),
            "virtual_wall": convert.format_walls(route.walls),
            "skip_area": convert.format_areas(route.areas),
        })
    galileo = {"map_name": name, "map_type": meta.map_type, "levels": list(meta.levels),
               "track": [list(p) for p in meta.track], "paths": paths}
    return map_archive(grid, {"galileo.json": json.dumps(galileo, ensure_ascii=False)})


@ROUTES.get("/navigation/download_map_from_robot")
def download_map_from_robot(ctx: Context, params: Params) -> Reply:
    """E25: the map archive (zip)."""
    name = params.text("map_name")
    ctx.store.map_record(name)
    return Response(archive(ctx, name), media_type="application/zip", headers={
        "Content-Disposition": f'attachment; filename="{_ascii_name(name)}.zip"'})


def _ascii_name(name: str) -> str:
    safe = "".join(c if c.isascii() and (c.isalnum() or c in "-_.") else "_" for c in name)
    return safe or "map"


def _member(zf: zipfile.ZipFile, name: str) -> bytes | None:
    try:
        info = zf.getinfo(name)
    except KeyError:
        return None
    if info.file_size > MAX_MEMBER:
        raise InvalidRequest("map_files", f"{name} is larger than {MAX_MEMBER} bytes")
    return zf.read(info)


def _read_archive(data: bytes) -> tuple[Any, dict[str, Any]]:
    """(the map, galileo.json) of an archive; InvalidRequest when it is not one."""
    try:
        zf = zipfile.ZipFile(io.BytesIO(data))
    except zipfile.BadZipFile:
        raise InvalidRequest("map_files", "not a zip archive (download_map_from_robot makes "
                             "one)") from None
    with zf, tempfile.TemporaryDirectory() as folder:
        try:
            meta_text = _member(zf, "map.yaml")
            image = _member(zf, "map.png")
            image_name = "map.png"
            if image is None:
                image, image_name = _member(zf, "map.pgm"), "map.pgm"
            extra = _member(zf, "galileo.json")
        except (zipfile.BadZipFile, OSError, RuntimeError) as exc:
            raise InvalidRequest("map_files", f"unreadable archive: {exc}") from None
        if meta_text is None or image is None:
            raise InvalidRequest("map_files", "the archive needs map.yaml and map.png")
        try:
            meta = safe_yaml.load(meta_text)
        except yaml.YAMLError as exc:
            raise InvalidRequest("map_files", f"map.yaml is not YAML: {exc}") from None
        if not isinstance(meta, dict):
            raise InvalidRequest("map_files", "map.yaml must hold a mapping")
        meta["image"] = image_name  # never a path the archive chose
        (Path(folder) / "map.yaml").write_text(yaml.safe_dump(meta), encoding="utf-8")
        (Path(folder) / image_name).write_bytes(image)
        try:
            grid = ros_map.load_map(Path(folder) / "map.yaml")
        except PolynavError as exc:
            raise InvalidRequest("map_files", f"bad map: {exc}") from None
    galileo: dict[str, Any] = {}
    if extra is not None:
        try:
            galileo = json.loads(extra)
        except ValueError:
            raise InvalidRequest("map_files", "galileo.json is not JSON") from None
        if not isinstance(galileo, dict):
            raise InvalidRequest("map_files", "galileo.json must hold an object")
    return grid, galileo


def _parsed_paths(galileo: dict[str, Any]) -> list[tuple[str, Any, Any, list[StopInput] | None,
                                                         Any, Any, bool]]:
    out = []
    for entry in galileo.get("paths", []):
        if not isinstance(entry, dict) or not isinstance(entry.get("name"), str):
            raise InvalidRequest("map_files", "galileo.json: a path needs a name")
        text = entry.get("path_data")
        polyline = convert.parse_path(text) if isinstance(text, str) else None
        map_points = bool(entry.get("map_points", False))
        stops = None if map_points else convert.parse_targets(entry.get("nav_points", ""))
        walls = convert.parse_walls(entry.get("virtual_wall", ""))
        areas = convert.parse_areas(entry.get("skip_area", ""))
        out.append((entry["name"], text, polyline, stops, walls, areas, map_points))
    return out


@ROUTES.post("/navigation/upload_map_to_robot")
def upload_map_to_robot(ctx: Context, params: Params) -> Reply:
    """E26 (multipart): store the archive's map as ``map_name``."""
    name = params.text("map_name")
    grid, galileo = _read_archive(params.file("map_files").content)
    map_type, levels = check_meta(str(galileo.get("map_type", "floor")),
                                  galileo.get("levels", [1]))
    track = tuple((float(p[0]), float(p[1]), float(p[2])) for p in galileo.get("track", []))
    paths = _parsed_paths(galileo)  # everything checked before the first write
    if ctx.runtime.status().map == name:
        raise Conflict(f"map {name!r} is in use: stop navigation before replacing it")
    ctx.store.save_map(name, grid)
    metas(ctx).put(name, MapMeta(levels, map_type, track))
    routes = sessions.routes(ctx)
    for path, text, polyline, stops, walls, areas, _map_points in paths:
        if polyline is not None:
            routes.save_polyline(name, path, polyline, text)
        if stops is not None:
            routes.set_stops(name, path, stops)
        routes.set_walls(name, path, walls)
        routes.set_areas(name, path, areas)
    log.info("galileo: map %r uploaded (%d paths)", name, len(paths))
    return {"status": "ok"}

