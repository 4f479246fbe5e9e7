"""Map operations (puwei-api §6, and ``POST /api/map/upload`` the intro lists, A8).

Maps are the site store's ROS map files. ``download/<name>.png`` is the stored picture and
``download/<name>.yaml`` the descriptor written in the document's form (``image: <name>.png``,
six decimals, puwei-api §6.4), both raw files; an error is the JSON envelope (A27). ``upload``
takes the same two files back (multipart parts, told apart by their ``.png``/``.yaml`` file
names) and saves them as map ``name``. ``list`` has no timestamps in the store: both times are
the picture's last write, in the robot's local time, ``YYYY-MM-DD HH:MM:SS`` (A26).
"""

from __future__ import annotations

import datetime as dt
import logging
import tempfile
from pathlib import Path
from typing import Any

import yaml
from starlette.responses import Response

from polynav import safe_yaml
from polynav.errors import Conflict, InvalidRequest, PolynavError
from polynav.maps import ros_map
from polynav.protocols.puwei.context import Context
from polynav.protocols.puwei.endpoint import RouteList
from polynav.protocols.puwei.launch import mapping_state
from polynav.protocols.puwei.request import PuweiRequest
from polynav.protocols.site_store import site_store as runtime_store
from polynav.store.site_store import SiteStore

log = logging.getLogger(__name__)

ROUTES = RouteList()

PNG, YAML = ".png", ".yaml"


def site_store(ctx: Context) -> SiteStore:
    """The site store of the context's runtime."""
    return runtime_store(ctx.runtime)


def _stamp(path: Path) -> str:
    try:
        return dt.datetime.fromtimestamp(path.stat().st_mtime).strftime("%Y-%m-%d %H:%M:%S")
    except OSError:
        return ""


@ROUTES.get("/api/map/save/:name")
def save(ctx: Context, request: PuweiRequest) -> None:
    """Save the map being built as ``name`` (mapping goes on; a map of that name is replaced,
    its points kept: the frame is the same)."""
    name = request.name()
    ctx.runtime.save_mapping(name, overwrite=True)
    mapping_state(ctx).saved_as = name
    log.info("puwei: map saved as %s", name)


@ROUTES.get("/api/map/list")
def map_list(ctx: Context, request: PuweiRequest) -> list[dict[str, Any]]:
    """``[{id, name, path, points, create_at, update_at}]``; ``id`` is the place in name
    order (1-based), ``points`` the count of the map's points, as text (A26)."""
    store = site_store(ctx)
    out = []
    for number, record in enumerate(store.maps(), start=1):
        stamp = _stamp(store.map_image_path(record.name))
        out.append({
            "id": number,
            "name": record.name,
            "path": f"/api/map/download/{record.name}{PNG}",
            "points": str(store.count_points(map_name=record.name)),
            "create_at": stamp,
            "update_at": stamp,
        })
    return out


@ROUTES.get("/api/map/delete/:name")
def delete(ctx: Context, request: PuweiRequest) -> None:
    """Delete map ``name`` with its points (not the one navigation runs on)."""
    name = request.name()
    store = site_store(ctx)
    store.map_record(name)  # NotFound first
    if ctx.runtime.status().map == name:
        raise Conflict(f"navigation runs on map {name!r}: stop it first")
    store.delete_map(name)
    log.info("puwei: map %s deleted", name)


def descriptor(ctx: Context, name: str) -> str:
    """The YAML of map ``name`` as the document writes it (puwei-api §6.4): ``mode`` is added
    only for a map the store keeps in scale mode, which reads wrong without it."""
    store = site_store(ctx)
    record = store.map_record(name)
    stored = store.map_image_path(name).with_suffix(YAML)
    try:
        meta = safe_yaml.load(stored.read_text(encoding="utf-8")) or {}
    except (OSError, yaml.YAMLError):
        meta = {}
    origin = record.origin
    lines = [
        f"image: {name}{PNG}",
        f"resolution: {record.resolution:.6f}",
        f"origin: [{origin.x:.6f}, {origin.y:.6f}, {origin.theta:.6f}]",
        "negate: 0",
        f"occupied_thresh: {float(meta.get('occupied_thresh', 0.65)):g}",
        f"free_thresh: {float(meta.get('free_thresh', 0.196)):g}",
    ]
    if meta.get("mode", "trinary") != "trinary":
        lines.append(f"mode: {meta['mode']}")
    return "\n".join(lines) + "\n"


@ROUTES.get("/api/map/download/:name")
def download(ctx: Context, request: PuweiRequest) -> Response:
    """``<name>.png`` (the picture) or ``<name>.yaml`` (the descriptor)."""
    file_name = request.name()
    if file_name.endswith(PNG):
        name = file_name[: -len(PNG)]
        site_store(ctx).map_record(name)
        data = site_store(ctx).map_image_path(name).read_bytes()
        return Response(data, media_type="image/png")
    if file_name.endswith(YAML):
        return Response(descriptor(ctx, file_name[: -len(YAML)]).encode("utf-8"),
                        media_type="application/x-yaml")
    raise InvalidRequest("name", f"ask for <map>{PNG} or <map>{YAML}, got {file_name!r}")


@ROUTES.post("/api/map/upload")
def upload(ctx: Context, request: PuweiRequest) -> None:
    """Save an uploaded ``<name>.png`` + ``<name>.yaml`` pair as map ``name`` (form field or
    query ``name``, else the picture's file name). An existing map of that name is refused
    unless ``overwrite=true``; the map navigation runs on is refused."""
    picture = descriptor_file = None
    for part in request.files.values():
        lower = part.filename.lower()
        if lower.endswith(PNG):
            picture = part
        elif lower.endswith(YAML):
            descriptor_file = part
    if picture is None or descriptor_file is None:
        raise InvalidRequest("files", "send <name>.png and <name>.yaml as multipart file parts")
    name = (request.form.get("name") or request.query.get("name")
            or Path(picture.filename).name[: -len(PNG)])
    if not name.strip():
        raise InvalidRequest("name", "must not be empty")
    overwrite = request.flag("overwrite", False)
    store = site_store(ctx)
    if name in {m.name for m in store.maps()}:
        if not overwrite:
            raise Conflict(f"map {name!r} exists: send overwrite=true to replace it")
        if ctx.runtime.status().map == name:
            raise Conflict(f"navigation runs on map {name!r}: stop it first")
    try:
        meta = safe_yaml.load(descriptor_file.content.decode("utf-8"))
    except (UnicodeDecodeError, yaml.YAMLError) as exc:
        raise InvalidRequest("yaml", f"not YAML: {exc}") from None
    if not isinstance(meta, dict):
        raise InvalidRequest("yaml", "must hold a mapping (image, resolution, origin ...)")
    meta["image"] = "map.png"  # never a path the upload chose
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "map.png").write_bytes(picture.content)
        (Path(folder) / "map.yaml").write_text(yaml.safe_dump(meta), encoding="utf-8")
        try:
            grid = ros_map.load_map(Path(folder) / "map.yaml")
        except PolynavError as exc:
            raise InvalidRequest("map", f"bad map files: {exc}") from None
    store.save_map(name, grid)
    log.info("puwei: map %s uploaded", name)
