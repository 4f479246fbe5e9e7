"""Target points of every path and the connections between maps (galileo-http-b §1.6, E46–E48).

Connections are the site store's (one store, several views): a Galileo ``direct`` connection
is stored as a direct connection between the two target points' map points, in the store's
JSON shape (``{"type": "direct", "from": {"map", "point"}, "to": {...}}``) that the multi-map
router reads, with the Galileo refs and ids kept beside it under ``"galileo"``. The record's
name is the Galileo ``id``. The site's lifts (``"type": "lift"`` records) are shown as
``elevator`` connections between the car's inside points on consecutive floors (their ``id`` is
``<car>:<floor>-<floor>``); they belong to the site and cannot be deleted here.

Decisions (A-26, A-4): exactly two points on two different maps; ``elevator`` connections are
not created over Galileo (polynav's lifts are cars serving floor maps, not elevator maps: they
come with the site); ``is_available: false`` is refused (the router has no such switch: delete
the connection to take it out of routing). A ref names a (map, path, index); the connection keeps
the point itself, so re-uploading target points does not move it, and ``GET`` reports the
point's current index in that path.
"""

from __future__ import annotations

import logging
import secrets
import uuid
from typing import Any

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.mapping import metas
from polynav.protocols.galileo.params import Params
from polynav.site import Point
from polynav.store.records import ConnectionRecord

log = logging.getLogger(__name__)

ROUTES = RouteList()


def _point_json(ctx: Context, point: Point, path: str, index: int) -> dict[str, Any]:
    meta = metas(ctx).get(point.map_name)
    return {"x": point.pose.x, "y": point.pose.y, "theta": point.pose.theta,
            "name": point.name, "map": point.map_name, "path": path, "index": index,
            "type": meta.map_type, "levels": list(meta.levels)}


def all_points(ctx: Context) -> list[dict[str, Any]]:
    """Every target point of every path of every map."""
    out: list[dict[str, Any]] = []
    book = sessions.routes(ctx)
    for record in ctx.store.maps():
        for path in book.names(record.name):
            route = book.route(record.name, path)
            try:
                points = book.stop_points(route)
            except NotFound as exc:  # a stop's point deleted through another API
                log.warning("galileo: path %s/%s skipped: %s", record.name, path, exc)
                continue
            out.extend(_point_json(ctx, p, path, i) for i, p in enumerate(points))
    return out


def _index_of(ctx: Context, map_name: str, path: str, point: str) -> int | None:
    try:
        route = sessions.routes(ctx).route(map_name, path)
    except NotFound:
        return None
    for index, stop in enumerate(route.stops):
        if stop.point == point:
            return index
    return None


def _enriched(ctx: Context, map_name: str, path: str, point: str, index: int
              ) -> dict[str, Any]:
    meta = metas(ctx).get(map_name) if _map_exists(ctx, map_name) else None
    current = _index_of(ctx, map_name, path, point)
    ref: dict[str, Any] = {"map": map_name, "path": path,
                           "index": current if current is not None else index}
    if meta is not None:
        ref.update({"type": meta.map_type, "levels": list(meta.levels)})
    return ref


def _map_exists(ctx: Context, map_name: str) -> bool:
    try:
        ctx.store.map_record(map_name)
    except NotFound:
        return False
    return True


def _direct_view(ctx: Context, record: ConnectionRecord) -> dict[str, Any] | None:
    data = record.data
    extra = data.get("galileo") if isinstance(data, dict) else None
    if not isinstance(extra, dict):
        return None
    refs = extra.get("points", [])
    points = [_enriched(ctx, r["map"], r["path"], r["point"], r["index"]) for r in refs]
    return {"_id": {"$oid": extra.get("oid", "")}, "points": points, "type": "direct",
            "is_available": True, "id": record.name}


def _lift_views(ctx: Context, record: ConnectionRecord) -> list[dict[str, Any]]:
    data = record.data
    stops = data.get("stops", []) if isinstance(data, dict) else []
    refs = []
    for stop in stops:
        if not isinstance(stop, dict):
            return []
        map_name, inside = stop.get("map"), stop.get("inside")
        if not isinstance(map_name, str) or not isinstance(inside, str):
            return []
        index = _index_of(ctx, map_name, sessions.current_path(ctx, map_name), inside)
        path = sessions.current_path(ctx, map_name)
        if index is None:
            index = _index_of(ctx, map_name, "default", inside)
            path = "default"
        if index is None:
            return []
        refs.append((stop.get("floor"), _enriched(ctx, map_name, path, inside, index)))
    views = []
    for (floor_a, a), (floor_b, b) in zip(refs, refs[1:], strict=False):
        views.append({"_id": {"$oid": ""}, "points": [a, b], "type": "elevator",
                      "is_available": True, "id": f"{record.name}:{floor_a}-{floor_b}"})
    return views


def all_connections(ctx: Context) -> list[dict[str, Any]]:
    out: list[dict[str, Any]] = []
    for record in ctx.store.connections():
        kind = record.data.get("type") if isinstance(record.data, dict) else None
        if kind == "direct":
            view = _direct_view(ctx, record)
            if view is not None:
                out.append(view)
        elif kind == "lift":
            out.extend(_lift_views(ctx, record))
    return out


@ROUTES.get("/navigation/point_connections")
def get_point_connections(ctx: Context, params: Params) -> Reply:
    """E46."""
    return {"points": all_points(ctx), "connections": all_connections(ctx)}


def _ref(raw: Any, n: int) -> tuple[str, str, int]:
    field = f"points[{n}]"
    if not isinstance(raw, dict):
        raise InvalidRequest(field, "must be an object {map, path, index}")
    map_name, path, index = raw.get("map"), raw.get("path"), raw.get("index")
    if not isinstance(map_name, str) or not isinstance(path, str):
        raise InvalidRequest(field, "map and path must be strings")
    if isinstance(index, bool) or not isinstance(index, int):
        raise InvalidRequest(f"{field}.index", f"must be an integer, got {index!r}")
    return map_name, path, index


@ROUTES.post("/navigation/point_connections")
def post_point_connections(ctx: Context, params: Params) -> Reply:
    """E47: add a direct connection; the reply echoes the request with ``is_available``,
    ``id`` and ``_id``."""
    kind = params.text("type")
    raw_points = params.structure("points")
    if not isinstance(raw_points, list) or len(raw_points) != 2:
        raise InvalidRequest("points", "a connection joins exactly two target points")
    if kind not in ("direct", "elevator"):
        raise InvalidRequest("type", f"must be 'direct' or 'elevator', got {kind!r}")
    if kind == "elevator":
        raise InvalidRequest("type", "polynav's elevator connections are the site's lifts "
                             "(listed by GET); create direct connections only")
    if not params.boolean("is_available", True):
        raise InvalidRequest("is_available", "a connection out of routing is deleted, not "
                             "stored unavailable")
    refs = [_ref(r, n) for n, r in enumerate(raw_points)]
    points = [sessions.target_point(ctx, m, p, i) for m, p, i in refs]
    if points[0].map_name == points[1].map_name:
        raise InvalidRequest("points", "the two target points must be on different maps")
    connection_id = str(uuid.uuid4())
    oid = secrets.token_hex(12)
    data = {
        "type": "direct",
        "from": {"map": points[0].map_name, "point": points[0].name},
        "to": {"map": points[1].map_name, "point": points[1].name},
        "galileo": {"oid": oid, "points": [
            {"map": m, "path": p, "index": i, "point": pt.name}
            for (m, p, i), pt in zip(refs, points, strict=True)]},
    }
    existing = ctx.store.connections()
    ctx.store.set_connections([*existing, ConnectionRecord(connection_id, data)])
    return {"points": [{"map": m, "path": p, "index": i} for m, p, i in refs], "type": kind,
            "is_available": True, "id": connection_id, "_id": {"$oid": oid}}


@ROUTES.delete("/navigation/point_connections")
def delete_point_connections(ctx: Context, params: Params) -> Reply:
    """E48."""
    connection_id = params.text("id")
    records = ctx.store.connections()
    kept = [r for r in records if r.name != connection_id]
    if len(kept) == len(records):
        car = connection_id.split(":", 1)[0]
        if ":" in connection_id and any(r.name == car for r in records):
            raise Conflict(f"{connection_id} is a lift of the site: it cannot be deleted here")
        raise NotFound("connection", connection_id)
    ctx.store.set_connections(kept)
    return {"status": "ok"}
