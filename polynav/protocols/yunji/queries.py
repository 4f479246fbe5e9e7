"""Yunji commands that query the site and the navigation stack: accessible points, distance
probes, path lengths, the planned path and lift status (§3.14.5-§3.14.6, §3.20-§3.22).

The answers come from :class:`polynav.runtime.site_queries.SiteQueries` (``runtime.queries``);
this module only converts parameters, floors and statuses.
"""

from __future__ import annotations

from polynav.geometry import Pose2D
from polynav.planning.errors import PlanningError
from polynav.protocols.yunji.context import (
    Context,
    Handler,
    Params,
    floor_level,
    lift_car,
    map_of_level,
    optional_int,
    parse_float,
    required,
    running_status,
)
from polynav.protocols.yunji.messages import Reply, Status
from polynav.routing.errors import NoRoute

GOAL_CAN_NOT_BE_REACHED = "goal can not be reached"  # §3.22, verbatim
# running_status values during which a lift ride is under way (§3.21, §A-P5).
LIFT_WINDOW = {
    "wait_lift_outside", "enter_lift", "avoid_lift", "take_lift", "exit_lift", "back_to_lift"
}


def _point(params: Params) -> tuple[float, float]:
    return parse_float("x", required(params, "x")), parse_float("y", required(params, "y"))


def _level(params: Params, name: str) -> int:
    required(params, name)
    level = optional_int(params, name)
    assert level is not None
    return level


def accessible_point_query(ctx: Context, params: Params) -> Reply:
    """§3.14.5: the nearest place within 3 m of (x, y) the robot fits and can reach, on the
    live costmap of the current floor; none -> ``GOAL_CAN_NOT_BE_REACHED`` (§A-P4)."""
    x, y = _point(params)
    try:
        px, py = ctx.runtime.queries.accessible_point(x, y)
    except PlanningError as exc:
        return Reply(Status.GOAL_CAN_NOT_BE_REACHED, str(exc))
    return Reply(results={"position": {"x": px, "y": py}})


def distance_probe(ctx: Context, params: Params) -> Reply:
    """§3.14.6: distances from (x, y) to the obstacles the lidar sees now (``-1``: beyond its
    reach, or it sees none) and to the static map's obstacles [m]."""
    x, y = _point(params)
    found = ctx.runtime.queries.distances(x, y)
    sensed = -1.0 if found.sensed is None else round(found.sensed, 6)
    return Reply(results={"env_dist": {"obstacle": sensed, "static": round(found.static, 6)}})


def make_plan(ctx: Context, params: Params) -> Reply:
    """§3.22: the length of the path polynav would plan; across floors, the in-map paths of
    the route through the lifts (a ride adds no length); no path or no route ->
    ``GOAL_CAN_NOT_BE_REACHED`` ``goal can not be reached`` (§A-P12)."""
    start = Pose2D(parse_float("start_x", required(params, "start_x")),
                   parse_float("start_y", required(params, "start_y")))
    goal = Pose2D(parse_float("goal_x", required(params, "goal_x")),
                  parse_float("goal_y", required(params, "goal_y")))
    start_map = map_of_level(ctx, _level(params, "start_floor"))
    goal_map = map_of_level(ctx, _level(params, "goal_floor"))
    try:
        if start_map != goal_map:
            length = ctx.runtime.route_length(start_map, start, goal_map, goal)
        else:
            length = ctx.runtime.queries.path_length(start_map, start, goal)
    except (PlanningError, NoRoute):
        return Reply(Status.GOAL_CAN_NOT_BE_REACHED, GOAL_CAN_NOT_BE_REACHED)
    return Reply(results={"distance": round(length, 3)})


def get_planned_path(ctx: Context, params: Params) -> Reply:
    """§3.20: the running goal's global path, at most 2000 points evenly spaced along it
    (§A-P9); ``[]`` when no move runs."""
    return Reply(results={"path": [[x, y] for x, y in ctx.runtime.queries.planned_path()]})


def lift_status(ctx: Context, params: Params) -> Reply:
    """§3.21: the level of the floor the car of the ride stands at (or last passed); only
    inside a lift ride (``wait_lift_outside`` .. ``exit_lift``), at any other time the spec's
    timeout error, as ``UNKNOWN_ERROR`` (§A-P5)."""
    snapshot = ctx.runtime.status()
    car = lift_car(snapshot)
    if running_status(snapshot) not in LIFT_WINDOW or car is None:
        return Reply(Status.UNKNOWN_ERROR, "timeout: the robot is not riding a lift")
    state = ctx.runtime.lift(car).state()
    return Reply(results={"current_floor": floor_level(ctx, state.current_floor)})


HANDLERS: dict[str, Handler] = {
    "/api/map/accessible_point_query": accessible_point_query,
    "/api/map/distance_probe": distance_probe,
    "/api/make_plan": make_plan,
    "/api/get_planned_path": get_planned_path,
    "/api/lift_status": lift_status,
}
