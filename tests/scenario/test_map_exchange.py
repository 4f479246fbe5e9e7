"""Maps exchanged with a dispatch server by a task (``upload_map_action``,
``download_map_action``), against a small dispatch server written here from the documented
exchange (docs/decisions.md: ``PUT``/``GET {url}/maps/{name}``, a zip of ``map.yaml`` and
``map.png``), on loopback."""

from __future__ import annotations

import io
import threading
import zipfile
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import numpy as np
import pytest
import yaml
from PIL import Image

from polynav.errors import ConfigError
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World


class Dispatch(BaseHTTPRequestHandler):
    """Keeps maps by name: PUT stores the body, GET answers it (404 if unknown)."""

    maps: dict[str, bytes] = {}
    fail = False

    def do_PUT(self) -> None:  # noqa: N802 - http.server's name
        body = self.rfile.read(int(self.headers["Content-Length"]))
        if self.fail:
            self.send_response(500)
        else:
            self.maps[self.path.removeprefix("/maps/")] = body
            self.send_response(201)
        self.send_header("Content-Length", "0")
        self.end_headers()

    def do_GET(self) -> None:  # noqa: N802
        body = self.maps.get(self.path.removeprefix("/maps/"))
        self.send_response(404 if body is None else 200)
        self.send_header("Content-Length", str(len(body or b"")))
        self.end_headers()
        self.wfile.write(body or b"")

    def log_message(self, *args: object) -> None:
        pass


@pytest.fixture
def server() -> Iterator[str]:
    Dispatch.maps = {}
    Dispatch.fail = False
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), Dispatch)
    threading.Thread(target=httpd.serve_forever, daemon=True).start()
    yield f"http://127.0.0.1:{httpd.server_address[1]}"
    httpd.shutdown()
    httpd.server_close()


@pytest.fixture
def runtime(world: World, tmp_path: Path, server: str) -> Iterator[RobotRuntime]:
    config = RuntimeConfig(people=False, dispatch_servers=(("lagrange", server),))
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        rt = RobotRuntime.simulated(store, world, config=config)
        rt.start_navigation("floor1")
        rt.advance(0.5)
        yield rt


def _run(rt: RobotRuntime, action: dict) -> dict:
    task = rt.tasks.create({"name": "transfer", "sub_tasks": [action]}, start=True)

    def ended() -> bool:
        rt.advance(0.05)  # the transfer runs in wall time on its own thread
        return rt.tasks.get(task["id"])["state"] not in ("WAITTING", "WORKING")

    for _ in range(400):
        if ended():
            break
    return rt.tasks.get(task["id"])


def _zip_map(cells: np.ndarray, resolution: float = 0.1) -> bytes:
    picture = io.BytesIO()
    Image.fromarray(cells).save(picture, format="PNG")
    meta = {"image": "map.png", "resolution": resolution, "origin": [1.0, 2.0, 0.0],
            "negate": 0, "occupied_thresh": 0.65, "free_thresh": 0.196}
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as zf:
        zf.writestr("map.yaml", yaml.safe_dump(meta))
        zf.writestr("map.png", picture.getvalue())
    return out.getvalue()


def test_the_map_in_use_is_uploaded_as_ros_map_files(runtime: RobotRuntime) -> None:
    task = _run(runtime, {"type": "upload_map_action", "server_id": "lagrange"})
    assert task["state"] == "COMPLETE", task
    assert task["blackboard"]["map.transferred"] == "floor1"
    with zipfile.ZipFile(io.BytesIO(Dispatch.maps["floor1"])) as zf:
        meta = yaml.safe_load(zf.read("map.yaml"))
        picture = np.array(Image.open(io.BytesIO(zf.read("map.png"))))
    sent = runtime.store.load_map("floor1")
    assert meta["resolution"] == pytest.approx(sent.info.resolution)
    assert picture.shape == (sent.info.height, sent.info.width)


def test_a_map_is_downloaded_into_the_site(runtime: RobotRuntime) -> None:
    cells = np.full((40, 60), 254, np.uint8)
    cells[10:12, :] = 0  # a wall
    Dispatch.maps["annex"] = _zip_map(cells)
    task = _run(runtime, {"type": "download_map_action", "server_id": "lagrange",
                          "map_id": "annex"})
    assert task["state"] == "COMPLETE", task
    got = runtime.store.load_map("annex")
    assert (got.info.width, got.info.height) == (60, 40)
    assert got.info.resolution == pytest.approx(0.1)
    assert got.info.origin.x == pytest.approx(1.0) and got.info.origin.y == pytest.approx(2.0)
    assert (got.data == 100).sum() == 2 * 60


@pytest.mark.parametrize(("action", "state", "reason"), [
    ({"type": "download_map_action", "server_id": "lagrange", "map_id": "nowhere"}, "FAIL",
     "404"),
    ({"type": "upload_map_action", "server_id": "elsewhere"}, "ERROR", "dispatch server"),
])
def test_transfers_that_cannot_happen(runtime: RobotRuntime, action: dict, state: str,
                                      reason: str) -> None:
    task = _run(runtime, {**action})
    leaf = task["tree"]["children"][0]
    assert leaf["state"] == state and reason in leaf["result"], leaf


def test_a_server_error_or_a_broken_archive_fails_and_changes_nothing(
        runtime: RobotRuntime) -> None:
    Dispatch.fail = True
    up = _run(runtime, {"type": "upload_map_action", "server_id": "lagrange"})
    assert up["tree"]["children"][0]["state"] == "FAIL"
    Dispatch.maps["junk"] = b"not a zip"
    down = _run(runtime, {"type": "download_map_action", "server_id": "lagrange",
                          "map_id": "junk"})
    assert down["tree"]["children"][0]["state"] == "FAIL"
    assert "zip" in down["tree"]["children"][0]["result"]
    assert "junk" not in [m.name for m in runtime.store.maps()]


def test_a_dispatch_server_off_loopback_is_refused_unless_allowed() -> None:
    with pytest.raises(ConfigError, match="dispatch_servers"):
        RuntimeConfig(dispatch_servers=(("far", "http://203.0.113.5/api"),))
    RuntimeConfig(dispatch_servers=(("far", "http://203.0.113.5/api"),),
                  task_callback_hosts=("203.0.113.0/24",))
