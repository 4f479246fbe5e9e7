"""Dependencies of the routes, as ``Annotated`` aliases (the full-stack-fastapi-template way).

The runtime and the site store hang on ``app.state``; ``create_app`` puts them there, so there is
no global to import and two apps in one process (tests) never share a robot.
"""

from __future__ import annotations

import logging
from typing import Annotated

from fastapi import Depends, Path, Query, Request

from polynav.api.examples import DEMO_FLOOR, DEMO_MAP, one
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
# The examples name the demo site's (polynav/api/examples.py).
MapNamePath = Annotated[
    Name, Path(description="the map's name", openapi_examples=one("a demo map", DEMO_MAP))
]
MapOfPoint = Annotated[
    Name | None, Query(description="the point's map, when the name is on several maps",
                       openapi_examples=one("a demo map", DEMO_MAP))
]
MapFilter = Annotated[Name | None, Query(description="only this map's points",
                                         openapi_examples=one("a demo map", DEMO_MAP))]
FloorFilter = Annotated[Name | None, Query(description="only this floor's points",
                                           openapi_examples=one("a demo floor", DEMO_FLOOR))]
# A point's name in a path: each route declares its own (polynav/api/routes/points.py), with its
# own example, so that the delete's example does not take the point the read's names.

