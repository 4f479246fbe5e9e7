"""Photos and videos of the robot's camera (galileo-http-a §3.14: E-58–E-63).

A photo is saved as ``<timestamp>.png`` and a video as ``<timestamp>.mkv`` in the data
directory's media folders, which the file-system API shows as ``/home/xiaoqiang/Pictures`` and
``/home/xiaoqiang/Videos`` (:mod:`~polynav.protocols.galileo.fs`). The timestamp is the
runtime's clock in milliseconds. ``file_timestamp`` is taken from the path
(``/system/saved_images/<file_timestamp>``, the form the document most probably had, A-20) or
the query; without it GET lists the names, oldest first, and DELETE is refused. The ``topic``
picks the camera: ``/camera_node/image_raw`` and ``/multi/front/image_raw`` the front one,
``/multi/back/image_raw`` the rear one. A recording is a task (A-36) that completes after its
``duration``; stopping the task saves what was recorded.
"""

from __future__ import annotations

from typing import Any

from starlette.responses import Response

from polynav.errors import InvalidRequest, NotFound
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.system_replies import OK
from polynav.protocols.galileo.system_tasks import VIDEO_ACTION, task_object, tasks
from polynav.robot.sim.devices.media import MediaFolder

ROUTES = RouteList()

DEFAULT_TOPIC = "/camera_node/image_raw"
TOPIC_VIEWS = {
    "/camera_node/image_raw": "front",
    "/multi/front/image_raw": "front",
    "/multi/back/image_raw": "back",
}
DEFAULT_DURATION = 10


def _view(params: Params) -> str:
    topic = params.text("topic", DEFAULT_TOPIC)
    if topic not in TOPIC_VIEWS:
        raise InvalidRequest("topic", f"no camera publishes {topic!r}; topics: "
                                      + ", ".join(sorted(TOPIC_VIEWS)))
    return TOPIC_VIEWS[topic]


def _listing_or_file(folder: MediaFolder, params: Params, media_type: str) -> Reply:
    if "file_timestamp" not in params or not str(params.values["file_timestamp"]):
        return folder.names()
    name = params.text("file_timestamp")
    path = folder.path(name)
    try:
        data = path.read_bytes()
    except FileNotFoundError:  # deleted since it was found
        raise NotFound("file", name) from None
    return Response(data, media_type=media_type)


def _delete(folder: MediaFolder, params: Params) -> dict[str, Any]:
    if "file_timestamp" not in params or not str(params.values["file_timestamp"]):
        raise InvalidRequest("file_timestamp", "name the file to delete")
    folder.delete(params.text("file_timestamp"))
    return {"status": OK}


@ROUTES.get("/system/saved_images/")
@ROUTES.get("/system/saved_images/{file_timestamp}")
def get_saved_images(ctx: Context, params: Params) -> Reply:
    """E-58: the photo names, or one photo (PNG)."""
    return _listing_or_file(ctx.runtime.peripherals.photos, params, "image/png")


@ROUTES.post("/system/saved_images")
def post_saved_images(ctx: Context, params: Params) -> Reply:
    """E-59: take a photo; ``{"image": <timestamp or filename>}``."""
    name = params.text("filename", None)
    return {"image": ctx.runtime.peripherals.take_photo(_view(params), name)}


@ROUTES.delete("/system/saved_images/")
@ROUTES.delete("/system/saved_images/{file_timestamp}")
def delete_saved_images(ctx: Context, params: Params) -> Reply:
    """E-60."""
    return _delete(ctx.runtime.peripherals.photos, params)


@ROUTES.get("/system/saved_videos/")
@ROUTES.get("/system/saved_videos/{file_timestamp}")
def get_saved_videos(ctx: Context, params: Params) -> Reply:
    """E-61: the video names, or one video (Matroska)."""
    return _listing_or_file(ctx.runtime.peripherals.videos, params, "video/x-matroska")


@ROUTES.post("/system/saved_videos")
def post_saved_videos(ctx: Context, params: Params) -> Reply:
    """E-62: start recording; the recording task."""
    view = _view(params)
    duration = params.integer("duration", DEFAULT_DURATION)
    name = params.text("filename", None)
    peripherals = ctx.runtime.peripherals
    job, stem = peripherals.start_video(view, float(duration), name)
    task = tasks(ctx).add(
        "video_task",
        {"type": VIDEO_ACTION, "topic": params.text("topic", DEFAULT_TOPIC),
         "duration": duration, "filename": stem},
        lambda: peripherals.job(job.job_id),
        peripherals.stop_video,
    )
    return task_object(task)


@ROUTES.delete("/system/saved_videos/")
@ROUTES.delete("/system/saved_videos/{file_timestamp}")
def delete_saved_videos(ctx: Context, params: Params) -> Reply:
    """E-63."""
    return _delete(ctx.runtime.peripherals.videos, params)
