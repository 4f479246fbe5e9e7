"""Yunji marker commands (§3.5) and ``get_current_location`` (§3.23): markers are the points
of a floor's map, their ``type`` / ``key`` a polynav point kind (custom types >= 1000 kept)."""

from __future__ import annotations

import math

from polynav.errors import InvalidRequest, NotFound
from polynav.geometry import Pose2D, yaw_to_quaternion
from polynav.protocols.yunji import containers
from polynav.protocols.yunji.context import (
    Context,
    Handler,
    Params,
    current_map,
    floor_level,
    map_of_level,
    optional_float,
    optional_int,
    parse_float,
    pose_json,
    required,
    running_status,
)
from polynav.protocols.yunji.messages import MarkerType, Reply
from polynav.site import Point, PointKind

DEFAULT_DISTANCE_THRESHOLD = 2.0

_KIND_BY_TYPE: dict[int, PointKind] = {
    MarkerType.GENERAL: PointKind.GENERAL,
    MarkerType.FRONT_DESK: PointKind.FRONT_DESK,
    MarkerType.LIFT_OUTSIDE: PointKind.LIFT_OUTSIDE,
    MarkerType.LIFT_INSIDE: PointKind.LIFT_INSIDE,
    MarkerType.GATE: PointKind.GATE,
    MarkerType.CHARGING_PILE: PointKind.CHARGER,
}

_TYPE_BY_KIND: dict[PointKind, int] = {
    PointKind.GENERAL: MarkerType.GENERAL,
    PointKind.INITIAL: MarkerType.GENERAL,
    PointKind.FRONT_DESK: MarkerType.FRONT_DESK,
    PointKind.CHARGER: MarkerType.CHARGING_PILE,
    PointKind.LIFT_OUTSIDE: MarkerType.LIFT_OUTSIDE,
    PointKind.LIFT_INSIDE: MarkerType.LIFT_INSIDE,
    PointKind.GATE: MarkerType.GATE,
    PointKind.CUSTOM: MarkerType.CUSTOM,
}


def marker_type(point: Point) -> int:
    """The marker ``key``: the kind's type, a custom point's own number (>= 1000)."""
    if point.kind is PointKind.CUSTOM and point.custom_type is not None:
        return point.custom_type
    return int(_TYPE_BY_KIND.get(point.kind, MarkerType.GENERAL))


def _marker_json(ctx: Context, point: Point, level: int) -> dict[str, object]:
    x, y, z, w = yaw_to_quaternion(point.pose.theta)
    return {
        "floor": level,
        "pose": {
            "orientation": {"w": w, "x": x, "y": y, "z": z},
            "position": {"x": point.pose.x, "y": point.pose.y, "z": 0.0},
        },
        "marker_name": point.name,
        "key": marker_type(point),
    }


def markers_query_list(ctx: Context, params: Params) -> Reply:
    """§3.5.2: keyed by name; without ``floor``, every floor (the current floor wins a name
    clash, §A-K6); ``null`` when there is none (§A-K5)."""
    level = optional_int(params, "floor")
    floors = ctx.store.floors()
    if level is not None:
        floors = [f for f in floors if f.level == level]
        if not floors:
            raise InvalidRequest("floor", f"no floor {level}")
    current = current_map(ctx)
    floors.sort(key=lambda f: f.map_name == current)
    results: dict[str, object] = {}
    for record in floors:
        for point in ctx.store.points(map_name=record.map_name):
            results[point.name] = _marker_json(ctx, point, record.level)
    return Reply(results=results or None)


def markers_insert(ctx: Context, params: Params) -> Reply:
    """§3.5.1: at the current pose, on the current map; an existing name is moved (§A-K1)."""
    name = required(params, "name")
    kind, custom = _kind(params)
    num = optional_int(params, "num", 1)
    map_name = current_map(ctx)
    point = Point(name, map_name, ctx.runtime.status().pose, kind, num, custom)
    try:
        ctx.store.point(map_name, name)
    except NotFound:
        ctx.store.add_point(point)
    else:
        ctx.store.update_point(map_name, name, point)
    return Reply()


def _kind(params: Params) -> tuple[PointKind, int | None]:
    """The point kind of ``type`` (§3.5.1), and the custom type number for types >= 1000."""
    marker_type = optional_int(params, "type", 0)
    assert marker_type is not None
    if marker_type >= MarkerType.CUSTOM:
        return PointKind.CUSTOM, marker_type
    kind = _KIND_BY_TYPE.get(marker_type)
    if kind is None:
        raise InvalidRequest(
            "type", f"must be 0, 1, 3, 4, 7, 11 or a custom type >= 1000, got {marker_type}"
        )
    return kind, None


def markers_delete(ctx: Context, params: Params) -> Reply:
    """§3.5.3: unknown name -> ``INVALID_REQUEST`` ``Marker Not Found``."""
    name = required(params, "name")
    ctx.store.delete_point(current_map(ctx), name)
    return Reply()


def markers_count(ctx: Context, params: Params) -> Reply:
    """§3.5.4: markers of the current map."""
    return Reply(results={"count": ctx.store.count_points(map_name=current_map(ctx))})


def markers_query_brief(ctx: Context, params: Params) -> Reply:
    """§3.5.5: ``name -> "<type>-<floor>"`` over every floor (as ``query_list``)."""
    current = current_map(ctx)
    floors = sorted(ctx.store.floors(), key=lambda f: f.map_name == current)
    results: dict[str, object] = {}
    for record in floors:
        for point in ctx.store.points(map_name=record.map_name):
            results[point.name] = f"{marker_type(point)}-{record.level}"
    return Reply(results=results)


def markers_insert_by_pose(ctx: Context, params: Params) -> Reply:
    """§3.5.6: at ``x, y, theta`` on ``floor`` (default: the current one); theta outside
    [-π, π] is refused rather than wrapped (§A-K4); an existing name on that map is moved."""
    name = required(params, "name")
    x = parse_float("x", required(params, "x"))
    y = parse_float("y", required(params, "y"))
    theta = parse_float("theta", required(params, "theta"))
    if abs(theta) > math.pi + 1e-9:
        raise InvalidRequest("theta", f"must be within [-pi, pi], got {theta}")
    kind, custom = _kind(params)
    num = optional_int(params, "num", 1)
    level = optional_int(params, "floor")
    map_name = current_map(ctx) if level is None else map_of_level(ctx, level)
    point = Point(name, map_name, Pose2D(x, y, theta), kind, num, custom)
    try:
        ctx.store.point(map_name, name)
    except NotFound:
        ctx.store.add_point(point)
    else:
        ctx.store.update_point(map_name, name, point)
    return Reply()


def get_current_location(ctx: Context, params: Params) -> Reply:
    """§3.23: every marker of the current map within ``distance_threshold``, nearest first."""
    threshold = optional_float(params, "distance_threshold", DEFAULT_DISTANCE_THRESHOLD)
    assert threshold is not None
    if threshold < 0.01:
        raise InvalidRequest("distance_threshold", f"must be >= 0.01, got {threshold}")
    s = ctx.runtime.status()
    near: list[tuple[float, Point]] = []
    for p in ctx.store.points(map_name=current_map(ctx)):
        d = math.hypot(p.pose.x - s.pose.x, p.pose.y - s.pose.y)
        if d <= threshold:
            near.append((d, p))
    near.sort(key=lambda item: item[0])
    return Reply(
        results={
            "current_floor": floor_level(ctx, s.floor),
            "current_pose": pose_json(s.pose),
            "near_markers": [
                {"distance": d, "key": marker_type(p), "marker_name": p.name} for d, p in near
            ],
            "running_status": containers.running_status(ctx, s, running_status(s)),
        }
    )


HANDLERS: dict[str, Handler] = {
    "/api/markers/query_list": markers_query_list,
    "/api/markers/insert": markers_insert,
    "/api/markers/delete": markers_delete,
    "/api/markers/count": markers_count,
    "/api/markers/query_brief": markers_query_brief,
    "/api/markers/insert_by_pose": markers_insert_by_pose,
    "/api/get_current_location": get_current_location,
}
