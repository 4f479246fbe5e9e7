"""Goals, stops, charging and moves of the androidmsg interface (ros1-nav-iface §2.1-2.3,
§3.3, §3.4, §3.17): ``/navi_targetgoal``, ``/navi_stop``, ``/autocharge``,
``/navi_targetgoalplan``, ``/get_position``, ``/set_navi_cmd``.

A goal names (floor, map, point); on another map than the one navigated it goes through the
runtime's router (lifts and connections), as every dialect's does. A robot not navigating yet
starts navigation on its floor's map first, as the vendor's robot is always in navigation mode.
"""

from __future__ import annotations

import math
from typing import Any

from polynav.errors import PolynavError
from polynav.planning.errors import PlanningError
from polynav.protocols.ros_graph import Graph, Message, RosError, Service, Subscription
from polynav.protocols.rosbridge.androidmsg import ids
from polynav.protocols.rosbridge.androidmsg.status import (
    NAVIGATION,
    NO_CHARGER,
    NO_POINT,
    PLAN_FOUND,
    PLAN_NOT_FOUND,
    Entries,
)
from polynav.site import Point, PointKind

#: /set_navi_cmd commands (§3.17): forward, backward, turn left, turn right, stop.
FORWARD, BACKWARD, LEFT, RIGHT, STOP = "1", "2", "3", "4", "5"


class Navigation(Entries):
    """The goal and motion entries over one runtime."""

    def declare(self, graph: Graph) -> None:
        graph.add_subscription(Subscription("/navi_targetgoal", "map_msgs/TargetGoal",
                                            self.target_goal))
        graph.add_subscription(Subscription("/navi_stop", "std_msgs/Int16", self.stop))
        graph.add_subscription(Subscription("/autocharge", "std_msgs/Int16", self.autocharge))
        graph.add_service(Service("/navi_targetgoalplan", "map_msgs/TargetGoalPlan", self.plan))
        graph.add_service(Service("/get_position", "map_msgs/GetPosition", self.position))
        graph.add_service(Service("/set_navi_cmd", "map_msgs/SetNaviCmd", self.navi_cmd))

    # -- topics --------------------------------------------------------------------------------

    def target_goal(self, msg: Message) -> None:
        point = self._target(msg)
        self._go(point.map_name, point.name)

    def stop(self, msg: Message) -> None:
        if ids.number(msg, "data") != 5:
            raise RosError("/navi_stop: 'data' must be 5 (stop)")
        runtime = self._runtime
        status = runtime.status()
        if status.navigation_state in ("running", "paused"):
            self._status.stopping()
        try:
            runtime.cancel()
        except PolynavError as exc:
            raise RosError(f"/navi_stop: {exc}") from None

    def autocharge(self, msg: Message) -> None:
        if ids.number(msg, "data") != 1:
            raise RosError("/autocharge: 'data' must be 1 (auto-charge)")
        map_name = self._map_in_use()
        chargers = [p for p in self._site.store.points(map_name=map_name)
                    if p.kind is PointKind.CHARGER]
        if not chargers:
            self._status.code(NAVIGATION, NO_CHARGER)
            raise RosError(f"/autocharge: map {map_name!r} has no charging pile")
        attempt = self._go(map_name, chargers[0].name)
        self._status.charging_started(attempt)

    # -- services ------------------------------------------------------------------------------

    def plan(self, args: Message) -> Message:
        kind = ids.number(args, "type")
        if kind not in (0, 1):
            raise RosError(f"'type' must be 0 (compute and navigate) or 1 (compute only), "
                           f"got {kind}")
        point = self._target(args)
        runtime = self._runtime
        snap = runtime.status()
        try:
            here_map: str | None = self._map_in_use()
        except RosError:
            here_map = None
        here_floor = self._site.floor_of_map(here_map)
        target_floor = self._site.floor_of_map(point.map_name)
        distance, status = -1.0, 0
        if point.map_name == here_map:
            try:
                distance = runtime.queries.path_length(point.map_name, snap.pose, point.pose)
            except (PlanningError, PolynavError):
                status = 1
        else:
            status = 2  # on another map: the route's length is not known before riding it
        if kind == 1:
            self._status.code(NAVIGATION, PLAN_FOUND if status == 0 else PLAN_NOT_FOUND)
        else:
            self._go(point.map_name, point.name)
        return {
            "status": status,
            "target_floor_id": target_floor.level if target_floor else 0,
            "target_map_id": ids.map_id(point.map_name),
            "target_point_id": ids.point_id(point),
            "local_floor_id": here_floor.level if here_floor else 0,
            "local_map_id": ids.map_id(here_map) if here_map else 0,
            "localX": snap.pose.x, "localY": snap.pose.y, "localYaw": snap.pose.theta,
            "distance": round(distance, 3) if distance >= 0 else -1.0,
        }

    def position(self, args: Message) -> Message:
        pose = self._runtime.status().pose
        return {"pose": {"x": pose.x, "y": pose.y, "z": 0.0}}

    def navi_cmd(self, args: Message) -> Message:
        cmd = args.get("cmd")
        if isinstance(cmd, int) and not isinstance(cmd, bool):
            cmd = str(cmd)  # the spec's type is string; a number is taken the same
        if cmd not in (FORWARD, BACKWARD, LEFT, RIGHT, STOP):
            raise RosError(f"'cmd' must be \"1\"..\"5\", got {cmd!r}")
        runtime = self._runtime
        try:
            if cmd == STOP:
                if runtime.local_move_active:
                    runtime.cancel()
                return {}
            amount = ids.number(args, "distance")
            if amount <= 0:
                raise RosError(f"'distance' must be > 0 (cm or degrees), got {amount}")
            if cmd in (FORWARD, BACKWARD):
                runtime.local_move(distance=(amount if cmd == FORWARD else -amount) / 100.0)
            else:
                turn = math.radians(amount)
                runtime.local_move(rotate=turn if cmd == LEFT else -turn)
        except PolynavError as exc:
            raise RosError(f"/set_navi_cmd: {exc}") from None
        return {}

    # -- helpers -------------------------------------------------------------------------------

    def _target(self, msg: dict[str, Any]) -> Point:
        floor_id, map_id, point_id = (ids.number(msg, k) for k in ("floor_id", "map_id",
                                                                     "point_id"))
        try:
            return self._site.point(floor_id, map_id, point_id)
        except RosError:
            self._status.code(NAVIGATION, NO_POINT)
            raise

    def _go(self, map_name: str, point: str) -> int:
        runtime = self._runtime
        try:
            if runtime.status().mode != "navigating":
                runtime.start_navigation(self._map_in_use())
            return runtime.go_to(point=point, map_name=map_name)
        except PolynavError as exc:
            raise RosError(str(exc)) from None
