"""The routes the web console draws from: keepouts, paths and the live scene, over real HTTP
(fake runtime, real site store), and the console's files served beside the API."""

from __future__ import annotations

import httpx

from polynav.web import STATIC_DIR
from tests.api.fakes import FakeRuntime

WALL = {"kind": "wall", "points": [[1.0, 1.0], [2.0, 1.0]], "thickness": 0.05}
ZONE = {"kind": "zone", "polygon": [[3.0, 3.0], [4.0, 3.0], [4.0, 4.0]]}


def test_keepouts_are_added_listed_replaced_and_navigation_reloads_them(
    client: httpx.Client, fake_runtime: FakeRuntime
) -> None:
    assert client.get("/api/maps/floor1/keepouts").json() == []
    answer = client.post("/api/maps/floor1/keepouts", json=WALL)
    assert answer.status_code == 201, answer.text
    assert answer.json() == [WALL]
    assert fake_runtime.keepouts_reloaded == 0  # not navigating on floor1: nothing to reload
    assert client.post("/api/navigation/start", json={"map": "floor1"}).status_code == 200
    both = client.post("/api/maps/floor1/keepouts", json=ZONE).json()
    assert both == [WALL, ZONE]
    assert fake_runtime.keepouts_reloaded == 1
    assert client.get("/api/maps/floor1/keepouts").json() == [WALL, ZONE]
    assert client.get("/api/maps/floor2/keepouts").json() == []
    # PUT with the list read before the last edit undoes it.
    assert client.put("/api/maps/floor1/keepouts", json=[WALL]).json() == [WALL]
    assert client.get("/api/maps/floor1/keepouts").json() == [WALL]
    assert fake_runtime.keepouts_reloaded == 2
    assert client.put("/api/maps/floor1/keepouts", json=[]).json() == []


def test_bad_keepouts_are_refused_with_the_apis_errors_and_change_nothing(
    client: httpx.Client,
) -> None:
    assert client.post("/api/maps/floor1/keepouts", json=WALL).status_code == 201
    for bad in ({"kind": "zone", "polygon": [[0, 0], [1, 1]]},
                {"kind": "wall", "points": []},
                {"kind": "circle", "x": 1.0, "y": 1.0, "radius": 0.0},
                {"kind": "blob"},
                {**WALL, "extra": 1}):
        answer = client.post("/api/maps/floor1/keepouts", json=bad)
        assert answer.status_code == 422, (bad, answer.text)
        assert answer.json()["error"]["code"] == "validation_error"
    assert client.put("/api/maps/floor1/keepouts", json=[WALL, {"kind": "x"}]).status_code == 422
    assert client.post("/api/maps/nowhere/keepouts", json=WALL).status_code == 404
    assert client.get("/api/maps/nowhere/keepouts").status_code == 404
    assert client.get("/api/maps/floor1/keepouts").json() == [WALL]


def test_paths_are_drawn_listed_redrawn_and_deleted(client: httpx.Client) -> None:
    assert client.get("/api/maps/floor1/paths").json() == []
    line = [[1.0, 1.0], [2.0, 1.5], [3.0, 1.0]]
    answer = client.put("/api/maps/floor1/paths/patrol", json={"points": line})
    assert answer.status_code == 200, answer.text
    assert answer.json() == {"name": "patrol", "map": "floor1", "points": line}
    assert client.get("/api/maps/floor1/paths").json() == [answer.json()]
    assert client.put("/api/maps/floor1/paths/patrol",
                      json={"points": line[:2]}).json()["points"] == line[:2]
    assert client.put("/api/maps/floor1/paths/patrol", json={"points": [[1, 1]]}).status_code \
        == 422
    assert client.delete("/api/maps/floor1/paths/patrol").status_code == 204
    assert client.get("/api/maps/floor1/paths").json() == []
    assert client.delete("/api/maps/floor1/paths/patrol").status_code == 404
    assert client.put("/api/maps/nowhere/paths/p", json={"points": line}).status_code == 404


def test_the_scene_has_the_running_goals_plan(client: httpx.Client) -> None:
    scene = client.get("/api/scene").json()
    assert scene["scan"] == [] and scene["path"] == [] and scene["people"] == []
    assert client.post("/api/navigation/start", json={"map": "floor1"}).status_code == 200
    assert client.post("/api/navigation/goal", json={"x": 3.0, "y": 4.0}).status_code == 202
    scene = client.get("/api/scene").json()
    assert scene["map"] == "floor1"
    assert scene["path"][-1] == [3.0, 4.0]


def test_the_console_page_and_its_files_are_served_beside_the_api(client: httpx.Client) -> None:
    page = client.get("/")
    assert page.status_code == 200
    assert page.headers["content-type"].startswith("text/html")
    assert page.text == (STATIC_DIR / "index.html").read_text()
    for name in ("app.js", "api.js", "view.js", "input.js", "edit.js", "tasks.js", "style.css"):
        answer = client.get(f"/web/{name}")
        assert answer.status_code == 200, name
        assert answer.content == (STATIC_DIR / name).read_bytes()
    assert client.get("/web/app.js").headers["content-type"].startswith("text/javascript")
    assert client.get("/web/nothing.js").status_code == 404
    assert "/" not in client.get("/openapi.json").json()["paths"]  # not part of the API
