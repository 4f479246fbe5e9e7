"""Dependencies of the routes, as ``Annotated`` aliases (the full-stack-fastapi-template way).

The runtime and the site store hang on ``app.state``; ``create_app`` puts them there, so there is
no global to import and two apps in one process (tests) never share a robot.
"""

from __future__ import annotations

import logging
from typing import Annotated

from fastapi import Depends, Path, Query, Request

from polynav.api.schemas import Name
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore

log = logging.getLogger(__name__)


def get_runtime(request: Request) -> RobotRuntime:
    """The RobotRuntime this app serves."""
    runtime: RobotRuntime = request.app.state.runtime
    return runtime


def get_store(request: Request) -> SiteStore:
    """The SiteStore of that runtime (maps, points, settings on disk)."""
    store: SiteStore = request.app.state.store
    return store


RuntimeDep = Annotated[RobotRuntime, Depends(get_runtime)]
StoreDep = Annotated[SiteStore, Depends(get_store)]

# Names in paths and queries obey the same schema as names in bodies, so the document says that
# a name with a control character is refused (422) and never reaches the store.
MapNamePath = Annotated[Name, Path(description="the map's name")]
PointNamePath = Annotated[Name, Path(description="the point's name")]
MapOfPoint = Annotated[
    Name | None, Query(description="the point's map, when the name is on several maps")
]
MapFilter = Annotated[Name | None, Query(description="only this map's points")]
FloorFilter = Annotated[Name | None, Query(description="only this floor's points")]
