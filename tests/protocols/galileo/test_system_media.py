"""Photos and videos over real HTTP (galileo-http-a E-58–E-63)."""

from __future__ import annotations

import io

from PIL import Image

from polynav.protocols.galileo.system_tasks import device_task, stop_device_task
from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/system/saved_images/": "test_photos_are_taken_listed_fetched_and_deleted",
    "POST /api/v1/system/saved_images": "test_photos_are_taken_listed_fetched_and_deleted",
    "DELETE /api/v1/system/saved_images/": "test_photos_are_taken_listed_fetched_and_deleted",
    "GET /api/v1/system/saved_videos/": "test_a_recording_task_saves_a_video_after_its_duration",
    "POST /api/v1/system/saved_videos": "test_a_recording_task_saves_a_video_after_its_duration",
    "DELETE /api/v1/system/saved_videos/":
        "test_a_recording_task_saves_a_video_after_its_duration",
}

TASK_FIELDS = {"id", "name", "loop_flag", "current_task", "state", "sub_tasks", "progress",
               "loop_count"}


def test_photos_are_taken_listed_fetched_and_deleted(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/saved_images/") == []
    first = galileo.ok("POST", "/system/saved_images", json={})["image"]
    galileo.runtime.advance(1.0)
    rear = galileo.ok("POST", "/system/saved_images",
                      json={"topic": "/multi/back/image_raw"})["image"]
    named = galileo.ok("POST", "/system/saved_images", json={"filename": "door"})["image"]
    assert named == "door" and first.isdigit() and int(rear) > int(first)
    assert galileo.ok("GET", "/system/saved_images/") == [first, rear, "door"]
    photo = galileo.get(f"/system/saved_images/{first}")
    assert photo.status_code == 200 and photo.headers["content-type"] == "image/png"
    assert Image.open(io.BytesIO(photo.content)).size == (320, 240)
    same = galileo.get("/system/saved_images/", file_timestamp=first)
    assert same.content == photo.content
    assert galileo.ok("DELETE", f"/system/saved_images/{first}") == {"status": "ok"}
    assert galileo.ok("DELETE", "/system/saved_images/", params={"file_timestamp": "door"}) == {
        "status": "ok"}
    assert galileo.ok("GET", "/system/saved_images/") == [rear]
    # Bad input changes nothing.
    assert galileo.delete("/system/saved_images/").status_code == 400
    assert galileo.delete(f"/system/saved_images/{first}").status_code == 404
    assert galileo.get("/system/saved_images/..%2Fx").status_code in (400, 404)
    assert galileo.post("/system/saved_images", {"topic": "/nope"}).status_code == 400
    assert galileo.post("/system/saved_images", {"filename": "../x"}).status_code == 400
    assert galileo.ok("GET", "/system/saved_images/") == [rear]


def test_a_recording_task_saves_a_video_after_its_duration(galileo: Harness) -> None:
    task = galileo.ok("POST", "/system/saved_videos", json={"duration": 3})
    assert set(task) == TASK_FIELDS and task["state"] == "WORKING"
    assert task["sub_tasks"][0]["type"] == "record_video_action"
    assert task["current_task"]["duration"] == 3
    busy = galileo.post("/system/saved_videos", {"duration": 3})
    assert busy.status_code == 409
    galileo.runtime.advance(3.1)
    done = device_task(galileo.server.ctx, task["id"])
    assert done is not None and done["state"] == "COMPLETE" and done["progress"] == 1.0
    (name,) = galileo.ok("GET", "/system/saved_videos/")
    video = galileo.get(f"/system/saved_videos/{name}")
    assert video.headers["content-type"] == "video/x-matroska"
    assert video.content[:4] == b"\x1a\x45\xdf\xa3" and b"V_MJPEG" in video.content[:400]
    # A second recording, stopped through the task: the file is saved.
    second = galileo.ok("POST", "/system/saved_videos",
                        json={"duration": 60, "filename": "clip",
                              "topic": "/multi/front/image_raw"})
    galileo.runtime.advance(2.0)
    stopped = stop_device_task(galileo.server.ctx, second["id"])
    assert stopped is not None and stopped["state"] == "CANCELLED"
    assert galileo.ok("GET", "/system/saved_videos/") == [name, "clip"]
    assert galileo.ok("DELETE", "/system/saved_videos/clip") == {"status": "ok"}
    assert galileo.ok("GET", "/system/saved_videos/") == [name]
    for body in ({"duration": 0}, {"duration": "long"}, {"topic": "/nope"}):
        assert galileo.post("/system/saved_videos", body).status_code == 400
    assert not galileo.runtime.peripherals.recorder.recording
    assert galileo.delete("/system/saved_videos/").status_code == 400
