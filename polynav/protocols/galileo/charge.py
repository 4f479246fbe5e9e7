"""Charging endpoints (galileo-http-b E28, E29, E35, E36).

The charge pile of a map is its first charger point (the same point the native API and the
Yunji adapter show). ``go_charge`` runs a task with one ``charge_action`` at the pile's pose: the
runtime's docking goal navigates to its approach and docks, so GalileoStatus goes ``chargeStatus`` 3
(finding) -> 4 (docking) -> 1 (charging) -> 2 (charged), or 5 (error). ``stop_charge`` cancels
that task; a robot already docked stays on the pile (it backs off at its next goal).
``POST charge_pose`` stores the robot's pose as the pile (normally while it sits on it).
"""

from __future__ import annotations

import logging

from polynav.errors import NotFound
from polynav.geometry import Pose2D
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo import task_objects as objects
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.site import Point, PointKind

log = logging.getLogger(__name__)

ROUTES = RouteList()

CHARGE_TASK = "charge task"
PILE_NAME = "charge_pile"


def _pose(pose: Pose2D) -> dict[str, float]:
    return {"x": float(pose.x), "y": float(pose.y), "theta": float(pose.theta)}


@ROUTES.get("/navigation/charge_pose")
def get_charge_pose(ctx: Context, params: Params) -> Reply:
    """E35: the pile of the map in use (404 when it has none)."""
    return _pose(sessions.charge_pile(ctx, sessions.current_map(ctx)).pose)


@ROUTES.post("/navigation/charge_pose")
def post_charge_pose(ctx: Context, params: Params) -> Reply:
    """E36: the robot's pose becomes the pile's (navigating: a pose on the map is needed)."""
    sessions.require_goals_allowed(ctx)
    snap = ctx.runtime.status()
    map_name = sessions.current_map(ctx)
    pose = Pose2D(snap.pose.x, snap.pose.y, snap.pose.theta)
    try:
        pile = sessions.charge_pile(ctx, map_name)
    except NotFound:
        ctx.store.add_point(Point(PILE_NAME, map_name, pose, PointKind.CHARGER))
    else:
        ctx.store.update_point(map_name, pile.name, Point(
            pile.name, map_name, pose, PointKind.CHARGER, pile.number, pile.custom_type))
    return _pose(pose)


@ROUTES.get("/navigation/go_charge")
def go_charge(ctx: Context, params: Params) -> Reply:
    """E28: navigate to the pile and dock; the charge task."""
    map_name = sessions.current_map(ctx)
    pile = sessions.charge_pile(ctx, map_name)
    sessions.require_goals_allowed(ctx)
    action = {"type": "charge_action", **_pose(pile.pose), "map": map_name}
    return objects.run(ctx, CHARGE_TASK, [action], kind=objects.CHARGE)


@ROUTES.get("/navigation/stop_charge")
def stop_charge(ctx: Context, params: Params) -> Reply:
    """E29: ``{"status": "ok", "task": <the cancelled charge task or null>}``."""
    return {"status": "ok", "task": objects.cancel_running(ctx, objects.CHARGE)}
