"""Following the drawn path to a goal, when the robot's setting asks for it (issue item 4).

The vendor's setting ``astar_path_changeability`` ("whether to detour", galileo-http-a §1.7) is
kept by the system-config module in ``<data>/galileo/system_config.json``; when it is ``false``
and the path in use has a drawn path file, a goal on that map is reached along the drawn path:
:mod:`polynav.planning.route_graph` finds the way along it (anchored at the path's target
points), thinned to waypoints about :data:`SPACING` apart, each a ``none_stop_nav_action``
passed within :data:`PASS_TOLERANCE` (no stop, no turn), then the goal as usual. Each leg is
still planned on the costmap, so the robot keeps clear of obstacles between waypoints. When the
robot or the goal is more than :data:`MAX_OFFSET` from the drawn path, or the path does not
join them, the goal is planned directly.
"""

from __future__ import annotations

import json
import logging
import math
from typing import Any

from polynav.geometry import Pose2D
from polynav.planning import route_graph
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo.context import Context

log = logging.getLogger(__name__)

SPACING = 1.0  # [m] between waypoints along the drawn path
PASS_TOLERANCE = 0.35  # [m]
MAX_OFFSET = 2.0  # [m] from the drawn path to the robot or the goal
SETTING = "astar_path_changeability"


def follows_drawn_paths(ctx: Context) -> bool:
    """Whether the robot's setting says not to detour (follow drawn paths)."""
    path = ctx.data_dir / "galileo" / "system_config.json"
    try:
        values = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return isinstance(values, dict) and values.get(SETTING) is False


def waypoint_actions(ctx: Context, map_name: str, path: str, goal: Pose2D
                     ) -> list[dict[str, Any]]:
    """The pass-through legs along the drawn path towards ``goal`` ([] when not following)."""
    if not follows_drawn_paths(ctx):
        return []
    try:
        route = sessions.routes(ctx).route(map_name, path)
        anchors = [(p.pose.x, p.pose.y) for p in sessions.routes(ctx).stop_points(route)]
    except LookupError:
        return []
    if not route.polyline:
        return []
    graph = route_graph.build(route.polyline, anchors=anchors)
    pose = ctx.runtime.status().pose
    start = (pose.x, pose.y)
    if graph.nearest(start)[1] > MAX_OFFSET or graph.nearest((goal.x, goal.y))[1] > MAX_OFFSET:
        return []
    way = route_graph.shortest_route(graph, start, (goal.x, goal.y))
    if way is None:
        log.info("galileo: the drawn path %s/%s does not join the robot and the goal",
                 map_name, path)
        return []
    points = route_graph.waypoints(way, SPACING)
    actions: list[dict[str, Any]] = []
    for here, nxt in zip(points, [*points[1:], (goal.x, goal.y)], strict=True):
        if math.dist(here, (goal.x, goal.y)) < PASS_TOLERANCE or math.dist(here, start) < 0.2:
            continue
        heading = math.atan2(nxt[1] - here[1], nxt[0] - here[0])
        actions.append({"type": "none_stop_nav_action", "x": float(here[0]),
                        "y": float(here[1]), "theta": heading, "radius": PASS_TOLERANCE,
                        "map": map_name})
    return actions
