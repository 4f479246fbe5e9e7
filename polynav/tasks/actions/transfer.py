"""Map exchange with a dispatch server: ``upload_map_action`` and ``download_map_action``
(galileo-tasks-bt-ws §5.3 #3, #4).

The vendor's robot sends its map to, or fetches one from, a Lagrange dispatch server named by
``server_id``. polynav keeps no dispatch servers (no address, no credentials to reach one), so
either action ends ``ERROR`` at its start, naming why: a task that needs the map moved stops
there, rather than going on as if it had been moved.
"""

from __future__ import annotations

from pydantic import Field

from polynav.errors import Conflict
from polynav.tasks.action import Action, Params, action_type
from polynav.tasks.node import Run

NO_DISPATCH = "polynav has no Lagrange dispatch server connection"


class UploadParams(Params):
    server_id: str = Field(min_length=1)


class DownloadParams(UploadParams):
    map_id: str = Field(min_length=1)


@action_type
class UploadMapAction(Action):
    """Send the map in use to dispatch server ``server_id``."""

    type = "upload_map_action"
    schema = UploadParams

    def begin(self, run: Run) -> None:
        raise Conflict(NO_DISPATCH)


@action_type
class DownloadMapAction(Action):
    """Fetch map ``map_id`` from dispatch server ``server_id``."""

    type = "download_map_action"
    schema = DownloadParams

    def begin(self, run: Run) -> None:
        raise Conflict(NO_DISPATCH)
