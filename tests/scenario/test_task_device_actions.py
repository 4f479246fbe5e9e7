"""Device, media, callback and roslaunch actions on the simulated demo robot (issue 32).

Each type is run in a task on the runtime and judged on what it drives (the axis, the camera,
the files, an HTTP server on 127.0.0.1), on its blackboard keys, and on its bad cases: bad
parameters refused at create, a device fault ``ERROR``, a cancel that stops what it drives.
"""

from __future__ import annotations

import http.server
import math
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from polynav.errors import ConfigError, InvalidRequest
from polynav.robot.sim.devices.axis import SimAxis
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World

CAMERA = {"ip": "", "port": 80, "username": "admin", "password": "polynav"}


def _runtime(world: World, tmp_path: Path, **config: Any) -> Iterator[RobotRuntime]:
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        rt = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False, **config))
        rt.start_navigation("floor1")
        rt.advance(0.5)
        yield rt


@pytest.fixture
def runtime(world: World, tmp_path: Path) -> Iterator[RobotRuntime]:
    yield from _runtime(world, tmp_path)


def _run(rt: RobotRuntime, *actions: dict[str, Any], timeout: float = 60.0) -> dict[str, Any]:
    task = rt.tasks.create({"name": "t", "sub_tasks": list(actions)}, start=True)
    assert rt.advance_until(
        lambda: rt.tasks.get(task["id"])["state"] not in ("WAITTING", "WORKING"), timeout)
    return rt.tasks.get(task["id"])


def _leaf(task: dict[str, Any], i: int = 0) -> dict[str, Any]:
    leaf: dict[str, Any] = task["tree"]["children"][i]
    return leaf


# -- camera and media --------------------------------------------------------------------------

def test_image_action_saves_a_photo_named_by_its_timestamp(runtime: RobotRuntime) -> None:
    task = _run(runtime, {"type": "image_action", "timestamp": 1683278160650},
                {"type": "image_action", "topic": "/multi/back/image_raw"})
    assert task["state"] == "COMPLETE"
    assert task["blackboard"]["image.file"].endswith(".png")
    assert (runtime.peripherals.photos.root / "1683278160650.png").read_bytes()[:4] == \
        b"\x89PNG"
    assert (runtime.peripherals.photos.root / task["blackboard"]["image.file"]).exists()


def test_video_record_action_completes_at_once_and_stops_when_the_task_ends(
        runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "film", "sub_tasks": [
        {"type": "video_record_action", "timestamp": 42, "duration": 60},
        {"type": "sleep_action", "wait_time": 3}]}, start=True)
    runtime.advance(0.2)
    assert _leaf(runtime.tasks.get(task["id"]))["state"] == "COMPLETE"
    assert runtime.peripherals.recorder.recording
    assert runtime.advance_until(lambda: runtime.tasks.get(task["id"])["state"] == "COMPLETE",
                                 10.0)
    runtime.advance(0.1)
    assert not runtime.peripherals.recorder.recording  # 3 s of 60: stopped with the task
    assert runtime.tasks.get(task["id"])["blackboard"]["video.file"] == "42.mkv"
    assert (runtime.peripherals.videos.root / "42.mkv").stat().st_size > 0


def test_a_video_shorter_than_the_task_stops_at_its_duration(runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "film", "sub_tasks": [
        {"type": "video_record_action", "duration": 1},
        {"type": "sleep_action", "wait_time": 3}]}, start=True)
    runtime.advance(1.5)
    assert not runtime.peripherals.recorder.recording
    assert runtime.tasks.get(task["id"])["state"] == "WORKING"


def test_cancelling_a_task_stops_its_recording(runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "film", "sub_tasks": [
        {"type": "video_record_action", "duration": 60}, {"type": "wait_req_action"}]},
        start=True)
    runtime.advance(1.0)
    assert runtime.peripherals.recorder.recording
    runtime.tasks.cancel(task["id"])
    assert not runtime.peripherals.recorder.recording


def test_onvif_move_reaches_the_pose_and_the_snapshot_is_saved(runtime: RobotRuntime) -> None:
    task = _run(runtime, {"type": "onvif_camera_move_action", **CAMERA, "x": 0.5, "y": -0.25,
                          "zoom": 0.5},
                {"type": "onvif_camera_snapshot_action", **CAMERA, "channel": 1})
    assert task["state"] == "COMPLETE"
    pose = runtime.peripherals.ptz_pose()
    assert (pose.pan, pose.tilt, pose.zoom) == (0.5, -0.25, 0.5)
    name = task["blackboard"]["onvif.snapshot"]
    assert name.endswith(".jpg") and (runtime.peripherals.snapshots.root / name).exists()


def test_onvif_with_a_wrong_password_is_an_error(runtime: RobotRuntime) -> None:
    task = _run(runtime, {"type": "onvif_camera_move_action", **CAMERA, "password": "guess",
                          "x": 0.5, "y": 0.0})
    assert task["state"] == "ERROR"
    assert "password" in _leaf(task)["result"]
    assert runtime.peripherals.ptz_pose().pan == 0.0


def test_cancelling_an_onvif_move_stops_the_camera(runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "pan", "sub_tasks": [
        {"type": "onvif_camera_move_action", **CAMERA, "x": 1.0, "y": 0.0}]}, start=True)
    runtime.advance(0.5)
    runtime.tasks.cancel(task["id"])
    stopped = runtime.peripherals.ptz_pose().pan
    runtime.advance(1.0)
    assert 0.0 < stopped < 1.0 and runtime.peripherals.ptz_pose().pan == stopped


# -- axes ----------------------------------------------------------------------------------------

def test_slide_position_move_completes_where_asked(runtime: RobotRuntime) -> None:
    task = _run(runtime, {"type": "slide_action", "mode": 1, "speed": 0.1, "pose": 0.3},
                {"type": "jacking_action", "mode": 3, "pose": 0.5})
    assert task["state"] == "COMPLETE", _leaf(task)["result"]
    assert task["blackboard"]["slide.position"] == pytest.approx(0.3)
    assert task["blackboard"]["jacking.position"] == pytest.approx(0.03)
    assert runtime.peripherals.axis_state("slide").position == pytest.approx(0.3)


def test_jacking_rotate_in_the_map_frame_takes_the_heading_off(runtime: RobotRuntime) -> None:
    heading = runtime.status().pose.theta
    task = _run(runtime, {"type": "jacking_rotate_action", "mode": 1, "angle": 1.0,
                          "frame_id": "map"})
    assert task["state"] == "COMPLETE"
    expected = math.remainder(1.0 - heading, 2 * math.pi)
    assert task["blackboard"]["jacking.angle"] == pytest.approx(expected, abs=1e-3)


def test_a_jog_runs_for_its_time(runtime: RobotRuntime) -> None:
    task = _run(runtime, {"type": "slide_action", "mode": 2},
                {"type": "slide_action", "mode": 0, "speed": 0.05, "time": 2.0})
    assert task["state"] == "COMPLETE"
    assert task["blackboard"]["slide.position"] == pytest.approx(0.1, abs=1e-3)


def test_an_axis_fault_during_the_move_is_an_error(runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "lift", "sub_tasks": [
        {"type": "jacking_action", "mode": 1, "pose": 0.05},
        {"type": "sleep_action", "wait_time": 1}]}, start=True)
    runtime.advance(1.0)
    axis = runtime.peripherals.devices.jacking
    assert isinstance(axis, SimAxis)
    runtime.run_between_ticks(lambda: axis.set_fault(runtime.now(), "motor overcurrent"))
    assert runtime.advance_until(lambda: runtime.tasks.get(task["id"])["state"] != "WORKING",
                                 2.0)
    done = runtime.tasks.get(task["id"])
    assert done["state"] == "ERROR"
    assert _leaf(done)["state"] == "ERROR" and "motor overcurrent" in _leaf(done)["result"]
    assert _leaf(done, 1)["state"] == "WAITTING"


def test_cancelling_an_axis_move_stops_the_axis(runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "slide", "sub_tasks": [
        {"type": "slide_action", "mode": 1, "pose": 0.5}]}, start=True)
    runtime.advance(6.0)
    assert runtime.peripherals.axis_state("slide").moving
    runtime.tasks.cancel(task["id"])
    state = runtime.peripherals.axis_state("slide")
    runtime.advance(1.0)
    assert not state.moving
    assert runtime.peripherals.axis_state("slide").position == state.position


def test_pausing_a_jog_stops_it_and_resuming_runs_the_time_left(runtime: RobotRuntime) -> None:
    task = runtime.tasks.create({"name": "jog", "sub_tasks": [
        {"type": "slide_action", "mode": 2},
        {"type": "slide_action", "mode": 0, "speed": 0.05, "time": 4.0}]}, start=True)
    assert runtime.advance_until(
        lambda: _leaf(runtime.tasks.get(task["id"]), 1)["state"] == "WORKING", 60.0)
    runtime.advance(1.0)
    runtime.tasks.pause(task["id"])
    runtime.advance(5.0)
    runtime.tasks.resume(task["id"])
    assert runtime.advance_until(lambda: runtime.tasks.get(task["id"])["state"] == "COMPLETE",
                                 10.0)
    assert runtime.tasks.get(task["id"])["blackboard"]["slide.position"] == pytest.approx(
        0.2, abs=0.01)


# -- callbacks -------------------------------------------------------------------------------

class _Handler(http.server.BaseHTTPRequestHandler):
    seen: list[tuple[str, str, bytes]] = []
    status = 200
    hang = threading.Event()

    def _answer(self) -> None:
        length = int(self.headers.get("Content-Length") or 0)
        type(self).seen.append((self.command, self.path, self.rfile.read(length)))
        if "slow" in self.path:
            type(self).hang.wait(5.0)
            return
        self.send_response(type(self).status)
        self.end_headers()
        self.wfile.write(b"x" * 5000 if "big" in self.path else b"thanks")

    do_GET = do_POST = do_PUT = _answer  # noqa: N815

    def log_message(self, *args: Any) -> None:
        pass


@pytest.fixture
def server() -> Iterator[str]:
    _Handler.seen = []
    _Handler.status = 200
    _Handler.hang = threading.Event()
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _Handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{httpd.server_address[1]}"
    _Handler.hang.set()
    httpd.shutdown()
    httpd.server_close()


def test_callback_posts_the_data_and_completes_on_2xx(runtime: RobotRuntime,
                                                      server: str) -> None:
    task = runtime.tasks.create({"name": "cb", "blackboard": {"where": "lobby"}, "sub_tasks": [
        {"type": "callback_action", "url": f"{server}/done", "method": "post",
         "data": {"at": "{where}", "n": 3}}]}, start=True)
    assert runtime.advance_until(lambda: runtime.tasks.get(task["id"])["state"] != "WORKING",
                                 600.0)
    done = runtime.tasks.get(task["id"])
    assert done["state"] == "COMPLETE"
    assert done["blackboard"]["callback.status"] == 200
    assert done["blackboard"]["callback.body"] == "thanks"
    assert _Handler.seen == [("POST", "/done", b'{"at": "lobby", "n": 3}')]


def test_callback_get_sends_the_data_as_the_query_and_caps_the_body(
        runtime: RobotRuntime, server: str) -> None:
    task = _run(runtime, {"type": "callback_action", "url": f"{server}/big?a=1",
                          "method": "GET", "data": {"b": "two"}}, timeout=600.0)
    assert task["state"] == "COMPLETE"
    assert _Handler.seen == [("GET", "/big?a=1&b=two", b"")]
    assert task["blackboard"]["callback.body"] == "x" * 4096


def test_callback_fails_on_a_non_2xx_answer(runtime: RobotRuntime, server: str) -> None:
    _Handler.status = 503
    task = _run(runtime, {"type": "callback_action", "url": f"{server}/x"}, timeout=600.0)
    assert task["state"] == "FAIL" and _leaf(task)["result"] == "HTTP 503"
    assert task["blackboard"]["callback.status"] == 503


def test_callback_fails_on_a_network_error_and_a_timeout(runtime: RobotRuntime,
                                                         server: str) -> None:
    closed = _run(runtime, {"type": "callback_action", "url": "http://127.0.0.1:9/"},
                  timeout=600.0)
    assert closed["state"] == "FAIL" and "network error" in _leaf(closed)["result"]
    assert closed["blackboard"]["callback.status"] == 0
    slow = _run(runtime, {"type": "callback_action", "url": f"{server}/slow",
                          "timeout": 0.3}, timeout=600.0)
    assert slow["state"] == "FAIL" and _leaf(slow)["result"].startswith("timeout")


def test_callback_to_another_host_is_refused_unless_configured(
        world: World, tmp_path: Path, runtime: RobotRuntime) -> None:
    task = _run(runtime, {"type": "callback_action", "url": "http://192.0.2.10/hook"})
    assert task["state"] == "ERROR" and "loopback" in _leaf(task)["result"]
    assert runtime.callbacks.allows("localhost") and runtime.callbacks.allows("127.8.0.1")
    allowed = next(_runtime(world, tmp_path / "other",
                            task_callback_hosts=("192.0.2.0/24", "hooks.example")))
    assert allowed.callbacks.allows("192.0.2.10") and allowed.callbacks.allows("HOOKS.example")
    assert not allowed.callbacks.allows("198.51.100.1")
    with pytest.raises(ConfigError, match="task_callback_hosts"):
        RuntimeConfig(task_callback_hosts=("http://x/",))


def test_cancelling_a_callback_forgets_its_answer(runtime: RobotRuntime, server: str) -> None:
    task = runtime.tasks.create({"name": "cb", "sub_tasks": [
        {"type": "callback_action", "url": f"{server}/slow", "timeout": 5}]}, start=True)
    runtime.advance(0.2)
    assert runtime.tasks.cancel(task["id"])["state"] == "CANCELLED"
    assert "callback.status" not in runtime.tasks.get(task["id"])["blackboard"]


# -- roslaunch -------------------------------------------------------------------------------

def test_roslaunch_is_recorded_and_nothing_is_started(runtime: RobotRuntime) -> None:
    command = "roslaunch xiaoqiang_track xiaoqiang_track.launch"
    task = _run(runtime, {"type": "roslaunch_action", "launch_cmd": command})
    assert task["state"] == "COMPLETE"
    assert task["blackboard"]["roslaunch.command"] == command
    assert _leaf(task)["result"].startswith("simulated")


# -- bad parameters ----------------------------------------------------------------------------

@pytest.mark.parametrize(("action", "match"), [
    ({"type": "image_action", "topic": "/nope"}, "no camera publishes"),
    ({"type": "video_record_action", "duration": 0}, "duration"),
    ({"type": "video_record_action", "video_url": "http://127.0.0.1/v.mkv"}, "not supported"),
    ({"type": "onvif_camera_move_action", **CAMERA, "x": 2.0, "y": 0.0}, "x"),
    ({"type": "onvif_camera_snapshot_action", **CAMERA, "channel": 2}, "channel"),
    ({"type": "slide_action", "mode": 5}, "mode"),
    ({"type": "slide_action", "mode": 0, "speed": 0.1}, "jog"),
    ({"type": "slide_action", "mode": 1, "speed": -0.1, "pose": 0.2}, "negative"),
    ({"type": "jacking_action", "mode": 3, "pose": 1.5}, "percentage"),
    ({"type": "jacking_rotate_action", "mode": 3}, "mode"),
    ({"type": "jacking_rotate_action", "mode": 1, "frame_id": "odom"}, "frame_id"),
    ({"type": "callback_action", "url": "ftp://127.0.0.1/x"}, "http"),
    ({"type": "callback_action", "url": "http://127.0.0.1/", "method": "BREW"}, "method"),
    ({"type": "callback_action"}, "url"),
    ({"type": "roslaunch_action", "launch_cmd": ""}, "launch_cmd"),
    ({"type": "roslaunch_action", "launch_cmd": "a\nb"}, "one line"),
])
def test_bad_parameters_are_refused_at_create(runtime: RobotRuntime, action: dict[str, Any],
                                              match: str) -> None:
    with pytest.raises(InvalidRequest, match=match):
        runtime.tasks.create({"name": "bad", "sub_tasks": [action]})
    assert runtime.tasks.list() == []
