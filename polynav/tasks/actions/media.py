"""The robot's cameras: ``image_action`` and ``video_record_action`` (galileo-tasks-bt-ws §5.3
#17, #16), and the network (ONVIF) camera: ``onvif_camera_move_action`` and
``onvif_camera_snapshot_action`` (#25, #26).

A camera is named by the ROS topic it publishes, as the document does (:data:`TOPIC_VIEWS`);
``timestamp`` names the file (epoch ms in the document's examples), else the runtime's clock
does. Files go where the runtime keeps media (its data directory), never to a path a task names.

A video is recorded for ``duration`` or until the task ends, whichever comes first, and the
action completes as soon as recording has started (A-16), so the task goes on filming what it
does next. ``video_url`` (downloading a video from a URL) is not supported: the action is
refused at create rather than silently recording the camera instead.

The network camera is the site's simulated one; a wrong address or login is refused when the
action starts (``ERROR``: bad parameters). A move completes once the camera stands at the pose
(not merely when the command was sent, so a snapshot after it shows what was asked for);
cancel stops the camera where it is.

Blackboard: ``image.file``, ``video.file``, ``onvif.snapshot`` (file names).
"""

from __future__ import annotations

from pydantic import Field, field_validator

from polynav.robot.devices import PtzPose
from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.robot import CameraLogin
from polynav.tasks.states import NodeState

DEFAULT_TOPIC = "/camera_node/image_raw"
TOPIC_VIEWS = {
    "/camera_node/image_raw": "front",
    "/multi/front/image_raw": "front",
    "/multi/back/image_raw": "back",
}
MAX_VIDEO = 600.0  # [s] the longest recording the robot makes
_PTZ_REACHED = 1e-6


class _CameraParams(Params):
    topic: str = DEFAULT_TOPIC
    timestamp: int | None = Field(default=None, ge=0, le=10**15)

    @field_validator("topic")
    @classmethod
    def _known_topic(cls, topic: str) -> str:
        if topic not in TOPIC_VIEWS:
            raise ValueError(f"no camera publishes {topic!r}; topics: "
                             f"{', '.join(sorted(TOPIC_VIEWS))}")
        return topic

    @property
    def view(self) -> str:
        return TOPIC_VIEWS[self.topic]

    @property
    def file_name(self) -> str | None:
        return None if self.timestamp is None else str(self.timestamp)


@action_type
class ImageAction(Action):
    """Take a photo with the camera of ``topic``; done once saved."""

    type = "image_action"
    schema = _CameraParams
    writes = ("image.file",)

    def begin(self, run: Run) -> None:
        p = self.p
        assert isinstance(p, _CameraParams)
        run.blackboard.write("image.file", run.robot.take_photo(p.view, p.file_name))
        self.end(run, NodeState.COMPLETE)


class VideoParams(_CameraParams):
    duration: float = Field(default=10.0, gt=0.0, le=MAX_VIDEO)
    video_url: str | None = None

    @field_validator("video_url")
    @classmethod
    def _no_download(cls, url: str | None) -> None:
        if url:
            raise ValueError("downloading a video from a URL is not supported: leave it out "
                             "to record the camera of topic")
        return None


@action_type
class VideoRecordAction(Action):
    """Start recording ``duration`` s (default 10) of the camera of ``topic``; done at once,
    the recording stopping early if the task ends first (A-16)."""

    type = "video_record_action"
    schema = VideoParams
    writes = ("video.file",)

    def begin(self, run: Run) -> None:
        p = self.p
        assert isinstance(p, VideoParams)
        name = run.robot.start_video(p.view, p.duration, p.file_name, task_id=run.task_id)
        run.blackboard.write("video.file", name)
        self.end(run, NodeState.COMPLETE)


class _OnvifParams(Params):
    ip: str = Field(default="", max_length=255)
    port: int = Field(default=80, ge=1, le=65535)
    username: str = Field(default="", max_length=255)
    password: str = Field(default="", max_length=255)

    def login(self) -> CameraLogin:
        return CameraLogin(self.ip, self.port, self.username, self.password)


class PtzMoveParams(_OnvifParams):
    x: float = Field(ge=-1.0, le=1.0)
    y: float = Field(ge=-1.0, le=1.0)
    zoom: float = Field(default=0.0, ge=0.0, le=1.0)


@action_type
class OnvifCameraMoveAction(Action):
    """Turn the network camera to pan ``x`` and tilt ``y`` (-1..1) and ``zoom`` (0..1), the
    ONVIF normalized space; done once it stands there."""

    type = "onvif_camera_move_action"
    schema = PtzMoveParams

    def target(self) -> PtzPose:
        p = self.p
        assert isinstance(p, PtzMoveParams)
        return PtzPose(p.x, p.y, p.zoom)

    def begin(self, run: Run) -> None:
        assert isinstance(self.p, PtzMoveParams)
        run.robot.ptz_move(self.p.login(), self.target())

    def poll(self, run: Run) -> NodeState | None:
        now, goal = run.robot.ptz_pose(), self.target()
        if max(abs(now.pan - goal.pan), abs(now.tilt - goal.tilt),
               abs(now.zoom - goal.zoom)) <= _PTZ_REACHED:
            return NodeState.COMPLETE
        return None

    def halt(self, run: Run) -> None:
        run.robot.ptz_stop()

    def hold(self, run: Run) -> None:
        run.robot.ptz_stop()

    def carry_on(self, run: Run) -> None:
        self.begin(run)


class SnapshotParams(_OnvifParams):
    channel: int = Field(default=1, ge=1, le=1)


@action_type
class OnvifCameraSnapshotAction(Action):
    """Save a snapshot of the network camera (channel 1, the only one); done once saved."""

    type = "onvif_camera_snapshot_action"
    schema = SnapshotParams
    writes = ("onvif.snapshot",)

    def begin(self, run: Run) -> None:
        assert isinstance(self.p, SnapshotParams)
        run.blackboard.write("onvif.snapshot", run.robot.ptz_snapshot(self.p.login()))
        self.end(run, NodeState.COMPLETE)
