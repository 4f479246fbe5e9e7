"""One store, several views (issue item 3): target points uploaded over Galileo are named points
the native API and the Yunji adapter list, a point added over the native API is a target point
of the map's Galileo ``default`` path, and a point deleted over Yunji leaves it (a stored path
that used it is refused naming it). Three real servers over one runtime, each spoken to over
its own HTTP."""

from __future__ import annotations

from collections.abc import Iterator

import httpx
import pytest

from polynav.api import ApiConfig, create_app
from polynav.protocols.yunji import YunjiConfig
from polynav.protocols.yunji.server import YunjiThread
from polynav.runtime.robot_runtime import RobotRuntime
from tests.api.server import ServerThread
from tests.protocols.galileo.conftest import Harness, serving


class Views:
    """The Galileo harness plus HTTP clients of the native API and Yunji's HTTP form."""

    def __init__(self, galileo: Harness, native: httpx.Client, yunji: httpx.Client) -> None:
        self.galileo = galileo
        self.native = native
        self.yunji = yunji

    def galileo_targets(self, map_name: str, path: str = "default") -> list[str]:
        """The names of (map, path)'s target points, in index order."""
        text = self.galileo.ok("GET", "/navigation/nav_points",
                               params={"map_name": map_name, "path_name": path})["path_data"]
        return [" ".join(line.split()[7:]) for line in text.splitlines()]

    def native_points(self, map_name: str) -> dict[str, tuple[float, float, float]]:
        reply = self.native.get("/api/points", params={"map": map_name})
        assert reply.status_code == 200, reply.text
        return {p["name"]: (p["x"], p["y"], p["theta"]) for p in reply.json()}

    def yunji_markers(self, floor: int) -> dict[str, object]:
        reply = self.yunji.get("/api/markers/query_list", params={"floor": floor})
        assert reply.status_code == 200 and reply.json()["status"] == "OK", reply.text
        results = reply.json()["results"]
        assert isinstance(results, dict)
        return results


@pytest.fixture
def views(runtime: RobotRuntime) -> Iterator[Views]:
    native = ServerThread(create_app(runtime, ApiConfig(port=0))).start()
    yunji = YunjiThread(runtime, YunjiConfig(port=0, http_port=0))
    try:
        with serving(runtime) as galileo, httpx.Client(
            base_url=native.url, timeout=20.0
        ) as native_http, httpx.Client(
            base_url=f"http://127.0.0.1:{yunji.http_port}", timeout=20.0
        ) as yunji_http:
            yield Views(galileo, native_http, yunji_http)
    finally:
        yunji.stop()
        native.stop()


def test_points_are_one_store_seen_through_three_dialects(views: Views) -> None:
    g = views.galileo
    targets = "5 10 0 1.5 0.1 0.1 0\n8 12.4 0 -0.5 0.2 0.2 1 gate A\n"
    g.ok("POST", "/navigation/nav_points",
         json={"map_name": "floor1", "path_name": "tour", "path_data": targets})
    native = views.native_points("floor1")
    assert native["tour_0"] == (5.0, 10.0, 1.5) and native["gate A"] == (8.0, 12.4, -0.5)
    markers = views.yunji_markers(1)
    assert {"tour_0", "gate A"} <= set(markers)

    # A point added over the native API is a target point of floor1's default path ...
    created = views.native.post("/api/points", json={"name": "bench", "map": "floor1",
                                                       "x": 9.0, "y": 12.4, "theta": 0.0})
    assert created.status_code == 201, created.text
    assert "bench" in views.galileo_targets("floor1")
    assert "bench" in views.yunji_markers(1)
    # ... and the robot goes there by its Galileo index.
    g.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": 1})
    assert g.advance_until(lambda: g.runtime.status().mode == "navigating", 10.0)
    index = views.galileo_targets("floor1").index("bench")
    task = g.ok("GET", "/navigation/move_to_index", params={"index": index})
    assert task["sub_tasks"][0]["x"] == 9.0

    # A point deleted over Yunji leaves the Galileo path and the native list.
    g.ok("GET", "/navigation/stop")
    # A point deleted over Yunji leaves the native list and the default path (the map's
    # points); a stored path that used it is refused naming the point, not silently shifted
    # (index 1 would become another point), until the path is uploaded again.
    assert views.galileo_targets("floor1", "tour") == ["", "gate A"]  # line 0 has no name
    deleted = views.yunji.get("/api/markers/delete", params={"name": "tour_0"})
    assert deleted.json()["status"] == "OK", deleted.text
    assert "tour_0" not in views.native_points("floor1")
    assert "tour_0" not in views.galileo_targets("floor1")
    names = {"map_name": "floor1", "path_name": "tour"}
    broken = g.get("/navigation/nav_points", **names)
    assert broken.status_code == 404 and "tour_0" in broken.json()["description"]
    g.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": 1})
    assert g.advance_until(lambda: g.runtime.status().mode == "navigating", 10.0)
    gone = g.get("/navigation/move_to_index", index=0, path="tour")
    assert gone.status_code == 404 and "tour_0" in gone.json()["description"]
    kept = g.ok("GET", "/navigation/move_to_index", params={"index": 1, "path": "tour"})
    assert (kept["sub_tasks"][0]["x"], kept["sub_tasks"][0]["y"]) == (8.0, 12.4)
    g.ok("GET", "/navigation/stop")
    g.ok("POST", "/navigation/nav_points",
         json={**names, "path_data": "8 12.4 0 -0.5 0.2 0.2 1 gate A\n"})
    assert views.galileo_targets("floor1", "tour") == ["gate A"]
