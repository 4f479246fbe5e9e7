"""Map exchange with a dispatch server: ``upload_map_action`` and ``download_map_action``
(galileo-tasks-bt-ws §5.3 #3, #4), on the runtime's map exchange
(:mod:`polynav.runtime.map_exchange`: servers by id, a zip of ROS map files over HTTP).

Upload sends the map in use; download saves map ``map_id`` in the site (replacing one of that
name). Done when the transfer is; a server that answers an error, cannot be reached or sends no
map ends ``FAIL``; a server id that is not configured, or no map in use to send, ``ERROR``
(the robot is not set up for it). Blackboard: ``map.transferred``, the map's name.
"""

from __future__ import annotations

from typing import Any

from pydantic import Field

from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run
from polynav.tasks.states import NodeState


class UploadParams(Params):
    server_id: str = Field(min_length=1)


class DownloadParams(UploadParams):
    map_id: str = Field(min_length=1, max_length=200)


class _Transfer(Action):
    writes = ("map.transferred",)

    def __init__(self, params: dict[str, Any], **kwargs: Any) -> None:
        super().__init__(params, **kwargs)
        self.transfer_id: int | None = None
        self.map_name = ""

    def poll(self, run: Run) -> NodeState | None:
        assert self.transfer_id is not None
        outcome = run.robot.transfer(self.transfer_id)
        if outcome is None:
            return None
        if not outcome.ok:
            self.result = outcome.reason
            return NodeState.FAIL
        run.blackboard.write("map.transferred", self.map_name)
        return NodeState.COMPLETE

    def reset(self) -> None:
        super().reset()
        self.transfer_id = None


@action_type
class UploadMapAction(_Transfer):
    """Send the map in use to dispatch server ``server_id``."""

    type = "upload_map_action"
    schema = UploadParams

    def begin(self, run: Run) -> None:
        assert isinstance(self.p, UploadParams)
        self.map_name = run.robot.current_map() or ""
        self.transfer_id = run.robot.upload_map(self.p.server_id)


@action_type
class DownloadMapAction(_Transfer):
    """Fetch map ``map_id`` from dispatch server ``server_id`` into the site."""

    type = "download_map_action"
    schema = DownloadParams

    def begin(self, run: Run) -> None:
        assert isinstance(self.p, DownloadParams)
        self.map_name = self.p.map_id
        self.transfer_id = run.robot.download_map(self.p.server_id, self.p.map_id)
