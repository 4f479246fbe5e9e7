"""The web console in a real browser (Debian's Chromium, headless) against a real robot.

Each test drives the page as a person would (clicks on the map canvas, keys, the buttons) and
checks the outcome through the native API, not through the page's own code: the robot arrives,
moves, the site holds the point, the plan avoids the wall.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import httpx

from tests.web.conftest import SPEED, Console, screenshot

# [s wall] for anything the robot does at SPEED. Every wait ends as soon as its condition
# holds, so this is only the ceiling: generous, because on CI's two busy cores the runtime falls
# well behind SPEED (once 17.9 s of simulated time at 8x, and a 15 s wait for the lobby gate
# ran out).
WAIT = 45.0


def screen_of(page: Any, x: float, y: float) -> tuple[float, float]:
    """Page coordinates of the world point (x, y) [m] on the map canvas."""
    local = page.evaluate("([x, y]) => window.polynav.view.toScreen(x, y)", [x, y])
    box = page.locator("#map").bounding_box()
    return box["x"] + local["x"], box["y"] + local["y"]


def click_world(page: Any, x: float, y: float, **options: Any) -> None:
    page.mouse.click(*screen_of(page, x, y), **options)


def wait_until(check: Callable[[], Any], timeout: float = WAIT) -> Any:
    deadline = time.monotonic() + timeout
    while True:
        value = check()
        if value:
            return value
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.02)


def api(console: Console) -> httpx.Client:
    return httpx.Client(base_url=console.server.url, timeout=10.0)


def point(http: httpx.Client, name: str) -> dict[str, Any]:
    answer = http.get(f"/api/points/{name}", params={"map": "floor1"})
    assert answer.status_code == 200, answer.text
    body: dict[str, Any] = answer.json()
    return body


def test_the_console_is_served_at_the_root_and_shows_the_map_and_the_robot(
    page: Any, console: Console
) -> None:
    assert page.title() == "polynav console"
    canvas = page.locator("#map")
    box = canvas.bounding_box()
    assert box["width"] > 600 and box["height"] > 500
    # The floor's map is drawn (its geometry from GET /api/maps), with the site's points.
    view = page.evaluate("({info: window.polynav.view.info, points: "
                         "window.polynav.view.layers.points.map(p => p.name), "
                         "robot: window.polynav.view.robot})")
    assert view["info"]["width"] == 820 and view["info"]["height"] == 500
    assert "lobby" in view["points"]
    pose = console.runtime.status().pose
    assert math.hypot(view["robot"]["x"] - pose.x, view["robot"]["y"] - pose.y) < 0.2
    # The canvas's pixels: the robot's colour at its place, the map's walls somewhere.
    sx, sy = screen_of(page, pose.x, pose.y)
    pixel = page.evaluate("""([x, y]) => {
        const c = document.getElementById('map'); const r = c.getBoundingClientRect();
        const k = c.width / r.width;
        const at = c.getContext('2d').getImageData((x - r.left) * k, (y - r.top) * k, 1, 1);
        return Array.from(at.data);
    }""", [sx, sy])
    assert pixel[1] > pixel[0] and pixel[1] > pixel[2], pixel  # green: the robot's footprint
    # The floor's doors and gates (GET /api/doors) are drawn with their state: the lobby's gate.
    page.wait_for_function("window.polynav.view.layers.doors.length > 0", timeout=WAIT * 1000)
    doors = page.evaluate("window.polynav.view.layers.doors.map(d => [d.name, d.kind, d.state])")
    floor = console.runtime.status().floor
    expected = {s.spec.name for s in console.runtime.door_states() if s.spec.floor == floor}
    assert expected and {name for name, _, _ in doors} == expected
    assert any(kind == "gate" for _, kind, _ in doors)
    page.wait_for_function("document.getElementById('st-mode').textContent === 'free'")
    screenshot(page, "overview")
    # At SPEED times real time, the stream is asked for about 10 statuses per wall second.
    page.wait_for_function(f"Math.abs(window.polynav.stream.rate - 10 / {SPEED}) < 0.5",
                           timeout=WAIT * 1000)


def test_clicking_a_named_point_sends_the_robot_there(page: Any, console: Console) -> None:
    with api(console) as http:
        lobby = point(http, "lobby")
    page.click("#nav-start")  # navigate on the floor shown
    page.wait_for_function("document.getElementById('st-mode').textContent === 'navigating'")
    page.click("[data-tool=go]")
    click_world(page, lobby["x"], lobby["y"])
    page.wait_for_function(
        "document.getElementById('st-nav').dataset.state === 'succeeded'", timeout=WAIT * 1000)
    assert "lobby" in page.text_content("#st-nav")
    pose = console.runtime.status().pose
    assert math.hypot(pose.x - lobby["x"], pose.y - lobby["y"]) < 0.3
    # The event comes on its own stream, not ordered with the status that showed 'succeeded'.
    page.wait_for_function(
        "[...document.querySelectorAll('#event-log li')]"
        ".some(i => i.dataset.kind === 'navigation_succeeded')", timeout=WAIT * 1000)
    screenshot(page, "arrived")


def test_the_keyboard_drives_the_robot(page: Any, console: Console) -> None:
    start = console.runtime.status().pose
    page.locator("#map").focus()
    page.keyboard.down("ArrowUp")
    wait_until(lambda: math.hypot(console.runtime.status().pose.x - start.x,
                                  console.runtime.status().pose.y - start.y) > 0.3)
    page.keyboard.up("ArrowUp")
    turned = console.runtime.status().pose.theta
    page.keyboard.down("a")  # turn left
    wait_until(lambda: abs(math.remainder(console.runtime.status().pose.theta - turned,
                                          math.tau)) > 0.3)
    page.keyboard.up("a")
    # The joystick: held forward, the robot drives; let go, it stops.
    pad = page.locator("#joystick").bounding_box()
    cx, cy = pad["x"] + pad["width"] / 2, pad["y"] + pad["height"] / 2
    here = console.runtime.status().pose
    page.mouse.move(cx, cy)
    page.mouse.down()
    page.mouse.move(cx, cy - pad["height"] / 2, steps=4)
    wait_until(lambda: math.hypot(console.runtime.status().pose.x - here.x,
                                  console.runtime.status().pose.y - here.y) > 0.3)
    page.mouse.up()
    wait_until(lambda: abs(console.runtime.status().linear) < 0.01)
    page.click("#estop")
    wait_until(lambda: console.runtime.status().estop_software)
    page.wait_for_function("document.getElementById('estop').textContent === 'RELEASE'")
    page.click("#estop")
    wait_until(lambda: not console.runtime.status().estop_software)


def test_the_initial_pose_is_set_by_dragging_on_the_map(page: Any, console: Console) -> None:
    page.click("#nav-start")
    page.wait_for_function("document.getElementById('st-mode').textContent === 'navigating'")
    subscription = console.runtime.bus.subscribe(maxlen=1000)
    pose = console.runtime.status().pose
    page.click("[data-tool=pose]")
    page.mouse.move(*screen_of(page, pose.x, pose.y))
    page.mouse.down()
    page.mouse.move(*screen_of(page, pose.x, pose.y + 1.0), steps=5)  # facing +y
    page.mouse.up()

    def initialized() -> list[Any]:
        return [e for e in subscription.get_nowait() if e.kind == "pose_initialized"]

    event = wait_until(initialized)[0]
    assert math.hypot(event.pose.x - pose.x, event.pose.y - pose.y) < 0.1
    assert abs(math.remainder(event.pose.theta - math.pi / 2, math.tau)) < 0.05
    console.runtime.bus.unsubscribe(subscription)


def test_a_task_made_from_points_runs_and_its_tree_shows_progress(
    page: Any, console: Console
) -> None:
    page.click("#tasks-panel summary")
    page.wait_for_selector("#task-points input[value=lobby]")
    page.fill("#task-name", "to the lobby")
    page.check("#task-points input[value=lobby]")
    page.click("#task-create")
    with api(console) as http:
        tasks = wait_until(lambda: http.get("/api/tasks").json())
        assert [t["name"] for t in tasks] == ["to the lobby"]
        assert "lobby" in str(tasks[0]["tree"])
    item = page.locator("#task-list li.task").first
    item.locator("button", has_text="Start").click()
    screenshot(page, "task-started")
    page.wait_for_selector("#task-list li.task[data-state=COMPLETE]", timeout=WAIT * 1000)
    with api(console) as http:
        lobby = point(http, "lobby")
    pose = console.runtime.status().pose
    assert math.hypot(pose.x - lobby["x"], pose.y - lobby["y"]) < 0.3
    assert "COMPLETE" in page.text_content("#task-list .tree")
    screenshot(page, "task-done")


def undo_offers(page: Any, label: str) -> None:
    """Wait until the console has taken the edit's answer and offers its undo.

    The store changes before the browser has read the answer; an undo pressed in between
    would undo the edit before it.
    """
    page.wait_for_function(
        "label => document.getElementById('undo').title === `undo: ${label} (Ctrl+Z)`",
        arg=label, timeout=WAIT * 1000)


def test_points_and_shapes_edited_on_the_map_are_saved_and_undone(
    page: Any, console: Console
) -> None:
    with api(console) as http:
        lobby = point(http, "lobby")
        x, y = lobby["x"] + 1.0, lobby["y"] - 0.5
        page.click("[data-tool=add-point]")
        page.once("dialog", lambda dialog: dialog.accept("dock_a"))
        click_world(page, x, y)
        added = wait_until(lambda: http.get("/api/points/dock_a",
                                            params={"map": "floor1"}).status_code == 200)
        assert added
        made = point(http, "dock_a")
        assert math.hypot(made["x"] - x, made["y"] - y) < 0.05
        page.wait_for_function("window.polynav.points.some(p => p.name === 'dock_a')")
        screenshot(page, "point-added")
        undo_offers(page, "add point dock_a")
        page.click("#undo")
        wait_until(lambda: http.get("/api/points/dock_a",
                                    params={"map": "floor1"}).status_code == 404)
        # Select a point, drag it, rename it, delete it, and undo the delete.
        kitchen = point(http, "kitchen")
        page.click("[data-tool=select]")
        click_world(page, kitchen["x"], kitchen["y"])
        page.wait_for_selector("#point-editor:not(.hidden)")
        page.mouse.move(*screen_of(page, kitchen["x"], kitchen["y"]))
        page.mouse.down()
        page.mouse.move(*screen_of(page, kitchen["x"] + 0.5, kitchen["y"]), steps=5)
        page.mouse.up()
        wait_until(lambda: abs(point(http, "kitchen")["x"] - (kitchen["x"] + 0.5)) < 0.05)
        undo_offers(page, "move point kitchen")
        page.fill("#point-name", "galley")
        page.click("#point-rename")
        wait_until(lambda: http.get("/api/points/galley",
                                    params={"map": "floor1"}).status_code == 200)
        assert http.get("/api/points/kitchen", params={"map": "floor1"}).status_code == 404
        page.wait_for_function("window.polynav.editor.selected?.name === 'galley'")
        page.click("#point-delete")
        wait_until(lambda: http.get("/api/points/galley",
                                    params={"map": "floor1"}).status_code == 404)
        undo_offers(page, "delete point galley")
        page.keyboard.press("Control+z")  # undo the delete: the point is back as it was
        wait_until(lambda: http.get("/api/points/galley",
                                    params={"map": "floor1"}).status_code == 200)
        assert point(http, "galley")["kind"] == kitchen["kind"]
        # A forbidden zone and a path, drawn corner by corner.
        x0, y0 = lobby["x"], lobby["y"]
        page.click("[data-tool=zone]")
        for dx, dy in ((0.5, 0.5), (1.5, 0.5), (1.5, 1.5)):
            click_world(page, x0 + dx, y0 + dy)
        page.keyboard.press("Enter")
        zones = wait_until(lambda: http.get("/api/maps/floor1/keepouts").json())
        assert zones[0]["kind"] == "zone" and len(zones[0]["polygon"]) == 3
        page.click("[data-tool=path]")
        page.once("dialog", lambda dialog: dialog.accept("to_desk"))
        click_world(page, x0, y0 - 1.0)
        click_world(page, x0 + 1.0, y0 - 2.0, click_count=2)  # a double-click ends it
        paths = wait_until(lambda: http.get("/api/maps/floor1/paths").json())
        assert paths[0]["name"] == "to_desk" and len(paths[0]["points"]) == 2
        page.wait_for_function(
            "window.polynav.view.layers.keepouts.some(k => k.kind === 'path')")
        screenshot(page, "edited")


def _segment_distance(p: list[float], a: list[float], b: list[float]) -> float:
    ax, ay = a
    bx, by = b
    t = ((p[0] - ax) * (bx - ax) + (p[1] - ay) * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2)
    t = max(0.0, min(1.0, t))
    return math.hypot(p[0] - ax - t * (bx - ax), p[1] - ay - t * (by - ay))


def _crosses(path: list[list[float]], a: list[float], b: list[float]) -> bool:
    def side(p: list[float]) -> float:
        return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])

    def on_ab(p: list[float], q: list[float]) -> bool:
        def s(u: list[float]) -> float:
            return (q[0] - p[0]) * (u[1] - p[1]) - (q[1] - p[1]) * (u[0] - p[0])
        return s(a) * s(b) <= 0

    pairs = zip(path, path[1:], strict=False)
    return any(side(p) * side(q) <= 0 and on_ab(p, q) for p, q in pairs)


def _first_plan(http: httpx.Client) -> list[list[float]]:
    """The plan of the goal just sent, read as soon as it exists; the goal is then cancelled
    so the robot stays about where it planned from."""
    path: list[list[float]] = wait_until(lambda: http.get("/api/scene").json()["path"])
    assert http.post("/api/navigation/cancel").status_code == 200
    return path


def test_a_virtual_wall_drawn_on_the_map_makes_the_next_plan_go_round_it(
    page: Any, console: Console
) -> None:
    with api(console) as http:
        goal = point(http, "front_desk")
        assert http.post("/api/navigation/start", json={"map": "floor1"}).status_code == 200
        page.wait_for_function("document.getElementById('st-mode').textContent === 'navigating'")
        assert http.post("/api/navigation/goal", json={"point": "front_desk"}).status_code == 202
        before = _first_plan(http)
        # A wall 1.4 m long across the middle of that plan, drawn with the Wall tool.
        mid = len(before) // 2
        (ax, ay), (bx, by) = before[mid - 4], before[mid + 4]
        norm = math.hypot(bx - ax, by - ay)
        nx, ny = -(by - ay) / norm, (bx - ax) / norm
        mx, my = before[mid]
        wall = [[mx + 0.7 * nx, my + 0.7 * ny], [mx - 0.7 * nx, my - 0.7 * ny]]
        assert _crosses(before, *wall)
        page.click("[data-tool=wall]")
        click_world(page, *wall[0])
        click_world(page, *wall[1])
        page.keyboard.press("Enter")
        stored = wait_until(lambda: http.get("/api/maps/floor1/keepouts").json())
        assert len(stored) == 1 and stored[0]["kind"] == "wall"
        for got, want in zip(stored[0]["points"], wall, strict=True):
            assert math.dist(got, want) < 0.05
        # The next plan, to the same point clicked on the map, goes round the wall.
        page.click("[data-tool=go]")
        click_world(page, goal["x"], goal["y"])
        after = _first_plan(http)
        assert not _crosses(after, *wall)
        assert min(_segment_distance(p, *wall) for p in after) > 0.2
        page.wait_for_function("window.polynav.view.layers.keepouts.length === 1")
        screenshot(page, "virtual-wall")


def test_the_console_fits_a_phone(browser: Any, console: Console) -> None:
    context = browser.new_context(viewport={"width": 390, "height": 844}, is_mobile=True,
                                  has_touch=True, device_scale_factor=2)
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    try:
        page.goto(console.url)
        page.wait_for_function("window.polynav && window.polynav.view.info !== null")
        page.wait_for_selector("#fleet-list li", state="attached")  # the top bar complete
        canvas, status = page.evaluate("""['map', 'status-panel'].map(id => {
            const r = document.getElementById(id).getBoundingClientRect();
            return {x: r.x, y: r.y, width: r.width, height: r.height};
        })""")
        assert canvas["width"] <= 390 and canvas["width"] > 350
        assert canvas["height"] > 300
        assert status["y"] >= canvas["y"] + canvas["height"]  # the panels under the map
        assert page.evaluate("document.documentElement.scrollWidth") <= 390  # no sideways scroll
        screenshot(page, "phone")
    finally:
        context.close()
    assert not errors, errors


def test_mapping_shows_the_map_growing_and_exploration_in_the_status(
    page: Any, console: Console
) -> None:
    page.click("#map-start")
    page.wait_for_function("document.getElementById('st-mode').textContent === 'mapping'")
    # The live map comes on the WebSocket and replaces the floor's picture.
    page.wait_for_function("window.polynav.shownImage === 'mapping'", timeout=WAIT * 1000)
    first = page.evaluate("window.polynav.view.info")
    assert first["width"] != 820 or first["height"] != 500  # the new map, not floor1's
    page.click("#map-explore")
    page.wait_for_function(
        "document.getElementById('st-mapping').textContent.includes('exploring')")
    area = console.runtime.status().mapping
    assert area is not None and area.exploration == "exploring"
    screenshot(page, "mapping")
    page.click("#map-cancel")
    page.wait_for_function("document.getElementById('st-mode').textContent === 'free'")


def test_the_status_panel_shows_the_door_the_robot_waits_at(
        page: Any, console: Console) -> None:
    """#38 item 1: a gate whose controller is silent keeps the robot before it; the status
    panel names the gate it waits for and its state, from the status stream."""
    console.runtime.set_door_answering("lobby_gate", False)
    with api(console) as http:
        assert http.post("/api/navigation/start", json={"map": "floor1"}).status_code == 200
        assert http.post("/api/navigation/goal",
                         json={"point": "corridor_west"}).status_code == 202
        page.wait_for_function(
            "document.getElementById('st-door').textContent === 'waits for lobby_gate closed'",
            timeout=WAIT * 1000)
        assert http.get("/api/status").json()["doors"]["waiting_for"] == {
            "name": "lobby_gate", "state": "closed"}


LEG_COLOR = (122, 74, 28)  # a standing cart's legs on the map (view.js drawCart)


def test_the_carts_are_drawn_where_they_stand_and_a_docked_one_is_the_load(
        page: Any, console: Console) -> None:
    """#38's carts on the map (their four legs, from GET /api/carts) and the robot's load in
    the status panel once it has docked to one."""
    with api(console) as http:
        cart = next(c for c in http.get("/api/carts").json()["carts"] if c["name"] == "cart_1")
        cos, sin = math.cos(cart["theta"]), math.sin(cart["theta"])
        legs = [(cart["x"] + u * cos - v * sin, cart["y"] + u * sin + v * cos)
                for u in (cart["length"] / 2, -cart["length"] / 2)
                for v in (cart["width"] / 2, -cart["width"] / 2)]
        pixel = """([x, y]) => {
            const view = window.polynav.view, canvas = document.getElementById('map');
            const ratio = canvas.width / canvas.getBoundingClientRect().width;
            const s = view.toScreen(x, y);
            return Array.from(canvas.getContext('2d').getImageData(
                Math.round(s.x * ratio), Math.round(s.y * ratio), 1, 1).data.slice(0, 3));
        }"""
        wait_until(lambda: all(tuple(page.evaluate(pixel, list(leg))) == LEG_COLOR
                               for leg in legs))
        screenshot(page, "carts")
        assert page.locator("#st-load").text_content() == "–"
        assert http.post("/api/navigation/start", json={"map": "floor1"}).status_code == 200
        assert http.post("/api/carts/dock", json={"cart": "cart_1"}).status_code == 200
        page.wait_for_function(
            "document.getElementById('st-load').textContent === 'cart_1 (cart, 40 kg)'",
            timeout=2 * WAIT * 1000)
        assert http.get("/api/status").json()["load"]["name"] == "cart_1"
