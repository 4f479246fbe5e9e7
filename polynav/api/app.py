"""The FastAPI application of the native API: a factory, never a global (STYLE R5)."""

from __future__ import annotations

import copy
import logging
import threading
from collections.abc import Callable
from typing import Any

from fastapi import FastAPI
from fastapi.routing import APIRoute

from polynav.api.auth_gate import install_login
from polynav.api.config import ApiConfig
from polynav.api.errors import FAULT, install_error_handlers
from polynav.api.routes import (
    carts,
    control,
    doors,
    fleet,
    keepouts,
    lifts,
    localization,
    mapless,
    mapping,
    maps,
    navigation,
    paths,
    points,
    robot,
    scene,
    schedules,
    settings,
    status,
    tasks,
    ws,
)
from polynav.api.routes.fleet import FleetListing
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from polynav.web import install_console

log = logging.getLogger(__name__)

ROUTERS = (
    status, maps, points, navigation, mapless, localization, mapping, control, settings, robot,
    fleet, lifts, doors, tasks, schedules, ws, keepouts, paths, scene, carts,
)


#: The OpenAPI document once built in this process, by whether the app asks for a login (the
#: only thing that changes it: the routes and their schemas are fixed when the package loads).
_DOCUMENTS: dict[bool, dict[str, Any]] = {}
_DOCUMENTS_LOCK = threading.Lock()


def _share_document(app: FastAPI, login: bool) -> None:
    """Build the OpenAPI document once per process, not once per app: it takes pydantic about
    0.5 s of CPU, paid otherwise by each robot's app of a building and by every app a client
    asks for ``/docs``. Each app gets its own copy, so no caller can change another's."""
    build: Callable[[], dict[str, Any]] = app.openapi

    def openapi() -> dict[str, Any]:
        if app.openapi_schema is None:
            with _DOCUMENTS_LOCK:
                if login not in _DOCUMENTS:
                    _DOCUMENTS[login] = build()
                app.openapi_schema = copy.deepcopy(_DOCUMENTS[login])
        return app.openapi_schema

    app.openapi = openapi  # type: ignore[method-assign]


def _operation_id(route: APIRoute) -> str:
    """Stable OpenAPI operation ids: the route function's name (unique across routers)."""
    return route.name


def create_app(
    runtime: RobotRuntime, config: ApiConfig, *, store: SiteStore | None = None,
    fleet: FleetListing | None = None,
) -> FastAPI:
    """Build the native API around one running robot.

    Args:
        runtime: the RobotRuntime to command; its tick thread is started and stopped by the
            caller (``polynav run``), so the app never owns the robot's lifetime.
        config: where it listens and how its WebSocket streams behave.
        store: the site store for maps and points; defaults to ``runtime.store``.
        fleet: the building's robots for ``GET /api/fleet`` (``polynav run --robots N``); a
            lone robot lists itself.

    Returns:
        The application, with OpenAPI at ``/docs`` and ``/openapi.json`` and the web console
        at ``/``.
    """
    from polynav import __version__

    app = FastAPI(
        title="polynav native API",
        version=__version__,
        description="Drive a polynav robot: status, maps, points, navigation, control, "
        "settings, tasks and their schedules, and a WebSocket of status and events.",
        generate_unique_id_function=_operation_id,
        responses=FAULT,
    )
    app.state.runtime = runtime
    app.state.store = store if store is not None else runtime.store
    app.state.api_config = config
    app.state.fleet = fleet
    #: Serial lines the dialects serve (name -> path), filled by ``polynav run``.
    app.state.links = {}
    #: Counters of refused input per dialect (name -> a reader), filled by ``polynav run``.
    app.state.diagnostics = {}
    install_error_handlers(app)
    for module in ROUTERS:
        app.include_router(module.router)
    install_console(app)
    if config.login_required:  # beyond loopback (or forced): docs/auth.md
        install_login(app, config)
    _share_document(app, config.login_required)
    return app
