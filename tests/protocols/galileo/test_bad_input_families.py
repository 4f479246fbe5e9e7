"""Bad input, family by family (issue acceptance, "Bad input"): an unknown map or path, a
missing or mistyped parameter, an index out of range, a call in the wrong state each give the
documented error — HTTP 4xx with ``{"status": "error", "description"}``, or for endpoints whose
reply has ``result`` a ``{"result": false, "description"}`` (galileo-http-b §2) — whose
description names the culprit, and change nothing (the digest of
:mod:`tests.protocols.galileo.state` is the same before and after). ``/fs`` escapes are in
``test_fs``; junk on every endpoint is ``test_bad_input``.

Each case runs with the robot free (not navigating) or navigating on floor1 at "lobby".
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import pytest

from tests.protocols.galileo.conftest import Harness
from tests.protocols.galileo.state import digest

RESULT = 200  # a ``{"result": false, ...}`` reply


@dataclass(frozen=True)
class Case:
    """One bad request and the error it must get.

    Attributes:
        family: the entry list's group (galileo-http-a/-b ``group``).
        method, path: the endpoint (under ``/api/v1``).
        params: the query string; ``body``: the JSON body.
        status: the HTTP status (``RESULT``: 200 with ``result: false``).
        word: a word the description must hold (the parameter or the unknown name).
        navigating: run while navigating on floor1, else with the robot free.
    """

    family: str
    method: str
    path: str
    status: int
    word: str
    params: dict[str, Any] = field(default_factory=dict)
    body: dict[str, Any] | None = None
    navigating: bool = False

    @property
    def label(self) -> str:
        state = "navigating" if self.navigating else "free"
        return f"{self.family}: {self.method} {self.path} {self.params or self.body} ({state})"


PATH_LINE = "5.5 12.5 0\n6.0 12.5 0\n"
TARGET_LINE = "5.5 12.5 0 0 0.1 0.1 0\n"
SQUARE = [[1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]]

CASES = [
    # navigation lifecycle (E9-E17, E37, E49, E56)
    Case("navigation", "GET", "/navigation/start", RESULT, "nowhere", {"map": "nowhere"}),
    Case("navigation", "GET", "/navigation/start", RESULT, "nopath",
         {"map": "floor1", "path": "nopath"}),
    Case("navigation", "GET", "/navigation/start", RESULT, "index",
         {"map": "floor1", "start_index": 999}),
    Case("navigation", "GET", "/navigation/start", RESULT, "start_index",
         {"map": "floor1", "start_index": "first"}),
    Case("navigation", "GET", "/navigation/start", RESULT, "level",
         {"map": "floor1", "level": "top"}),
    Case("navigation", "GET", "/navigation/reload", 404, "nowhere", {"map": "nowhere"},
         navigating=True),
    Case("navigation", "GET", "/navigation/reload", 400, "map", navigating=True),
    Case("navigation", "GET", "/navigation/reload", 404, "nopath",
         {"map": "floor2", "path": "nopath"}, navigating=True),
    Case("navigation", "GET", "/navigation/reload", 409, "navigat", {"map": "floor2"}),
    Case("navigation", "GET", "/navigation/switch_map", 404, "nowhere",
         {"map_name": "nowhere"}),
    Case("navigation", "GET", "/navigation/switch_map", 400, "map_name"),
    Case("navigation", "POST", "/navigation/init_pose", 400, "y", body={"x": 5, "z": 0},
         navigating=True),
    Case("navigation", "POST", "/navigation/init_pose", 400, "x",
         body={"x": "left", "y": 12, "theta": 0}, navigating=True),
    Case("navigation", "POST", "/navigation/init_pose", 409, "navigat",
         body={"x": 5.5, "y": 12.5, "theta": 0}),
    Case("navigation", "PUT", "/navigation/update_map", 400, "enabled",
         body={"enabled": "perhaps"}),
    # tasks-nav (E27, E30, E31, E57)
    Case("tasks-nav", "GET", "/navigation/move_to_index", 409, "navigat", {"index": 1}),
    Case("tasks-nav", "GET", "/navigation/move_to_index", 400, "index", navigating=True),
    Case("tasks-nav", "GET", "/navigation/move_to_index", 400, "index", {"index": "two"},
         navigating=True),
    Case("tasks-nav", "GET", "/navigation/move_to_index", 400, "index", {"index": 99},
         navigating=True),
    Case("tasks-nav", "GET", "/navigation/move_to_index", 404, "nopath",
         {"index": 1, "path": "nopath"}, navigating=True),
    Case("tasks-nav", "GET", "/navigation/move_to_index", 404, "nomap",
         {"index": 1, "map": "nomap"}, navigating=True),
    Case("tasks-nav", "POST", "/navigation/start_nav_task", 400, "theta",
         body={"x": 8.0, "y": 12.4}, navigating=True),
    Case("tasks-nav", "POST", "/navigation/start_nav_task", 400, "y",
         body={"x": 8.0, "y": "north", "theta": 0}, navigating=True),
    Case("tasks-nav", "POST", "/navigation/start_nav_task", 409, "navigat",
         body={"x": 8.0, "y": 12.4, "theta": 0}),
    Case("tasks-nav", "POST", "/navigation/start_nav_task", 404, "nomap",
         body={"x": 8.0, "y": 12.4, "theta": 0, "map": "nomap"}, navigating=True),
    Case("tasks-nav", "POST", "/navigation/multi_map_task", 400, "to",
         body={"from": {"map": "floor1", "path": "default", "index": 1}}),
    Case("tasks-nav", "POST", "/navigation/multi_map_task", 404, "nomap",
         body={"from": {"map": "floor1", "path": "default", "index": 1},
               "to": {"map": "nomap", "path": "default", "index": 0}}),
    Case("tasks-nav", "POST", "/navigation/multi_map_task", 400, "index",
         body={"from": {"map": "floor1", "path": "default", "index": 1},
               "to": {"map": "floor2", "path": "default", "index": 99}}),
    # charge and loop (E28-E29, E32-E36)
    Case("charge", "GET", "/navigation/go_charge", 409, "navigat"),
    Case("charge", "POST", "/navigation/charge_pose", 409, "navigat"),
    Case("loop", "POST", "/navigation/loop_task", 400, "wait_time", navigating=True),
    Case("loop", "POST", "/navigation/loop_task", 400, "wait_time",
         body={"wait_time": "soon"}, navigating=True),
    Case("loop", "POST", "/navigation/loop_task", 400, "wait_time", body={"wait_time": -3},
         navigating=True),
    Case("loop", "POST", "/navigation/loop_task", 409, "navigat", body={"wait_time": 1}),
    # paths and target points (E38-E45)
    Case("paths", "GET", "/navigation/path", 404, "nowhere", {"map_name": "nowhere"}),
    Case("paths", "GET", "/navigation/path", 404, "nopath",
         {"map_name": "floor1", "path_name": "nopath"}),
    Case("paths", "POST", "/navigation/path", 404, "nowhere",
         body={"map_name": "nowhere", "path_name": "p", "path_data": PATH_LINE}),
    Case("paths", "POST", "/navigation/path", 400, "path_data",
         body={"map_name": "floor1", "path_name": "p"}),
    Case("paths", "POST", "/navigation/path", 400, "path_name",
         body={"map_name": "floor1", "path_data": PATH_LINE}),
    Case("paths", "PUT", "/navigation/path", 400, "path_data",
         body={"map_name": "floor1", "path_name": "p", "path_data": ["not", "text"]}),
    Case("paths", "DELETE", "/navigation/path", 404, "nopath",
         {"map_name": "floor1", "path_name": "nopath"}),
    Case("paths", "DELETE", "/navigation/path", 404, "nowhere",
         {"map_name": "nowhere", "path_name": "default"}),
    Case("targets", "GET", "/navigation/nav_points", 404, "nopath",
         {"map_name": "floor1", "path_name": "nopath"}),
    Case("targets", "POST", "/navigation/nav_points", 404, "nowhere",
         body={"map_name": "nowhere", "path_name": "dock", "path_data": TARGET_LINE}),
    Case("targets", "POST", "/navigation/nav_points", 400, "path_data",
         body={"map_name": "floor1", "path_name": "dock", "path_data": "5.5 twelve 0"}),
    Case("targets", "DELETE", "/navigation/nav_points", 404, "nopath",
         {"map_name": "floor1", "path_name": "nopath"}),
    # connections (E46-E48)
    Case("connections", "POST", "/navigation/point_connections", 400, "points",
         body={"type": "direct"}),
    Case("connections", "POST", "/navigation/point_connections", 400, "index",
         body={"type": "direct", "is_available": True,
               "points": [{"map": "floor1", "path": "default", "index": 1},
                          {"map": "floor2", "path": "default", "index": 99}]}),
    Case("connections", "DELETE", "/navigation/point_connections", 404, "no-such",
         {"id": "no-such"}),
    Case("connections", "DELETE", "/navigation/point_connections", 400, "id"),
    # areas (E50-E55)
    Case("areas", "GET", "/navigation/skip_area", 404, "nowhere",
         {"map_name": "nowhere", "path_name": "default"}),
    Case("areas", "POST", "/navigation/skip_area", 404, "nowhere",
         body={"map_name": "nowhere", "path_name": "default", "skip_area": "1 1 2 2\n"}),
    Case("areas", "POST", "/navigation/skip_area", 400, "skip_area",
         body={"map_name": "floor1", "path_name": "default", "skip_area": "1 one\n"}),
    Case("areas", "POST", "/navigation/virtual_wall", 400, "virtual_wall",
         body={"map_name": "floor1", "path_name": "default"}),
    Case("areas", "DELETE", "/navigation/virtual_wall", 404, "nowhere",
         {"map_name": "nowhere", "path_name": "default"}),
    # local tasks (E58-E62)
    Case("tasks-local", "GET", "/navigation/start_local_move", 409, "navigat",
         {"distance": 0.5, "angle": 0, "method": 0}),
    Case("tasks-local", "GET", "/navigation/start_local_move", 400, "method",
         {"distance": 0.5, "angle": 0}, navigating=True),
    Case("tasks-local", "GET", "/navigation/start_nav_and_local_move", 400, "index",
         {"index": 99, "distance": 0.5, "angle": 0, "method": 0}, navigating=True),
    Case("tasks-local", "GET", "/navigation/start_nav_local_move_io", 400, "port",
         {"index": 2, "distance": 0.5, "angle": 0, "method": 0, "level": 1, "port": 9},
         navigating=True),
    Case("tasks-local", "GET", "/navigation/start_local_move_index", 400, "index",
         {"index": -9, "start_rotate_enable": 1, "target_rotate_enable": 1},
         navigating=True),
    Case("tasks-local", "GET", "/navigation/start_local_move_target", 400, "xy_tolerance",
         {"x": 1, "y": 0, "theta": 0, "frame_id": "map", "xy_tolerance": 0, "yaw_tolerance":
          0.1, "timeout": 5, "start_rotate_enable": 1, "target_rotate_enable": 1},
         navigating=True),
    # coverage (E65)
    Case("coverage", "POST", "/navigation/coverage_path", 400, "border",
         body={"swath_angle": 0, "op_width": 0.5, "turn_radius": 0.5,
               "headland_width": 0.0}),
    Case("coverage", "POST", "/navigation/coverage_path", 400, "op_width",
         body={"swath_angle": 0, "op_width": -1, "turn_radius": 0.5, "headland_width": 0.0,
               "border": SQUARE}),
    # maps, map files (E1-E8, E18-E26)
    Case("map", "GET", "/map/stop", RESULT, "mapping"),
    Case("map", "GET", "/map/update", RESULT, "nowhere", {"map": "nowhere"}),
    Case("map", "POST", "/map/current_map_image", RESULT, "mapping", body={"name": "m"}),
    Case("map", "GET", "/map/start", RESULT, "navigat", navigating=True),
    Case("map-files", "GET", "/navigation/map_pgm", 404, "nowhere", {"name": "nowhere"}),
    Case("map-files", "GET", "/navigation/map_png", 400, "name"),
    Case("map-files", "GET", "/navigation/saved_maps", 400, "type", {"type": "boat"}),
    Case("map-files", "GET", "/navigation/download_map_from_robot", 404, "nowhere",
         {"map_name": "nowhere"}),
    Case("map-files", "POST", "/navigation/upload_map_to_robot", 400, "map_files",
         {"map_name": "new"}),
    # system families (galileo-http-a)
    Case("system", "PUT", "/system/speed", RESULT, "speed_x",
         body={"speed_x": "fast", "speed_theta": 0}),
    Case("io", "POST", "/system/io", 400, "port", body={"port": "7", "level": "1"}),
    Case("io", "PUT", "/system/bw_io", 400, "level", body={"port": 1, "level": 5}),
    Case("voice", "PUT", "/system/volume", 400, "value", body={"value": 300}),
    Case("slide", "GET", "/system/slide_move_to", 400, "pose", {"speed": 0.1, "pose": "top"}),
    Case("ros", "GET", "/system/topic", 404, "/nothing", {"topic_name": "/nothing"}),
    Case("onvif", "GET", "/system/onvif_camera/goto_preset", 400, "ip", {"preset": "1"}),
]


def _navigate(g: Harness) -> None:
    reply = g.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": 1})
    assert reply["result"] is True, reply
    assert g.advance_until(lambda: g.runtime.status().mode == "navigating", 10.0)
    g.runtime.advance(0.5)


@pytest.mark.parametrize("navigating", [False, True], ids=["free", "navigating"])
def test_bad_input_gives_the_documented_error_and_changes_nothing(
    galileo: Harness, navigating: bool
) -> None:
    if navigating:
        _navigate(galileo)
    failures = []
    for case in (c for c in CASES if c.navigating == navigating):
        before = digest(galileo.runtime, galileo.server)
        response = galileo.request(case.method, case.path, params=case.params, json=case.body)
        body = response.json()
        galileo.runtime.advance(0.3)  # anything it had started would show by now
        if response.status_code != case.status:
            failures.append(f"{case.label}: HTTP {response.status_code} {body}")
            continue
        if case.status == RESULT:
            ok = isinstance(body, dict) and body.get("result") is False
        else:
            ok = isinstance(body, dict) and body.get("status") == "error"
        description = body.get("description", "") if isinstance(body, dict) else ""
        if not ok or case.word not in str(description):
            failures.append(f"{case.label}: {body}")
        elif digest(galileo.runtime, galileo.server) != before:
            failures.append(f"{case.label}: changed the state")
    assert failures == [], "\n".join(failures)


def test_every_http_b_family_has_a_case() -> None:
    from tests.protocols.galileo import spec

    families = {e["group"] for e in spec.HTTP_B.values()}
    without = families - {c.family for c in CASES} - {"sensors", "landmarks"}
    assert without == set()


def test_the_digest_sees_a_change(galileo: Harness) -> None:
    """The control: a good request of the kinds above does change the digest."""
    before = digest(galileo.runtime, galileo.server)
    galileo.ok("POST", "/navigation/nav_points",
               json={"map_name": "floor1", "path_name": "dock", "path_data": TARGET_LINE})
    after = digest(galileo.runtime, galileo.server)
    assert after["routes"] != before["routes"] and after["points"] != before["points"]
    galileo.ok("POST", "/system/io", json={"port": "1", "level": "1"})
    assert digest(galileo.runtime, galileo.server)["io"] != after["io"]
