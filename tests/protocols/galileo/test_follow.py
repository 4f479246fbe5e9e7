"""Following the drawn path when the robot's setting says not to detour (issue item 4)."""

from __future__ import annotations

import json
import math

from tests.protocols.galileo.conftest import Harness

# Lobby east along the corridor, a dense stroke as clients draw it, 0.25 m apart.
STROKE = [(5.5 + 0.25 * i, 12.5) for i in range(33)]  # to (13.5, 12.5)
PATH = "".join(f"{x:g} {y:g} 0\n" for x, y in STROKE)
TARGETS = "5.5 12.5 0 0 0.1 0.1 0\n13.5 12.5 0 0 0.1 0.1 0\n"


def _setting(g: Harness, follow: bool) -> None:
    path = g.runtime.store.data_dir / "galileo" / "system_config.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"astar_path_changeability": not follow}), encoding="utf-8")


def _prepare(g: Harness) -> None:
    names = {"map_name": "floor1", "path_name": "corridor"}
    g.ok("POST", "/navigation/path", json={**names, "path_data": PATH})
    g.ok("POST", "/navigation/nav_points", json={**names, "path_data": TARGETS})
    g.ok("GET", "/navigation/start", params={"map": "floor1", "path": "corridor",
                                              "start_index": 0})
    g.advance_until(lambda: g.runtime.status().mode == "navigating", 10.0)


def test_goal_follows_the_drawn_path_through_waypoints(galileo: Harness) -> None:
    _setting(galileo, follow=True)
    _prepare(galileo)
    task = galileo.ok("GET", "/navigation/move_to_index", params={"index": 1})
    legs = task["sub_tasks"][:-1]
    assert len(legs) >= 5 and all(a["type"] == "none_stop_nav_action" for a in legs)
    assert all(abs(a["y"] - 12.5) < 1e-6 for a in legs)  # every waypoint on the stroke
    closest = [math.inf] * len(legs)  # how near the robot came to each waypoint
    state: dict[str, str] = {}

    def done() -> bool:
        pose = galileo.runtime.simulation.true_pose
        for i, a in enumerate(legs):
            closest[i] = min(closest[i], math.hypot(pose.x - a["x"], pose.y - a["y"]))
        state.update(galileo.ok("GET", "/task", params={"id": task["id"]}))
        return state["state"] in ("COMPLETE", "ERROR")

    assert galileo.advance_until(done, 120.0, step=0.2)
    assert state["state"] == "COMPLETE"
    assert max(closest) < 0.5, closest  # passed every waypoint of the drawn path
    pose = galileo.runtime.simulation.true_pose
    assert math.hypot(pose.x - 13.5, pose.y - 12.5) < 0.15


def test_without_the_setting_the_goal_is_planned_directly(galileo: Harness) -> None:
    _setting(galileo, follow=False)
    _prepare(galileo)
    task = galileo.ok("GET", "/navigation/move_to_index", params={"index": 1})
    assert len(task["sub_tasks"]) == 1
