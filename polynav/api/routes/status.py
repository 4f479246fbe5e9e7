"""GET /api/status: the prebuilt snapshot, never computed in the request."""

from __future__ import annotations

import logging

from fastapi import APIRouter, Request
from fastapi.responses import JSONResponse

from polynav.api.deps import RuntimeDep
from polynav.api.schemas import StatusOut

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api", tags=["status"])


@router.get(
    "/status",
    operation_id="get_status",
    response_model=StatusOut,
    summary="The robot's status snapshot",
)
def get_status(runtime: RuntimeDep, request: Request) -> JSONResponse:
    """Mode, map, pose, velocity, battery, e-stop, localization and navigation state, and the
    serial lines the dialects serve.

    The runtime refreshes the snapshot on its own clock; this reads it as it is (O(1)).
    """
    body = runtime.status().to_dict()
    body["links"] = dict(request.app.state.links)
    return JSONResponse(body)


@router.get(
    "/diagnostics",
    operation_id="get_diagnostics",
    response_model=dict[str, dict[str, int]],
    summary="What the dialects' wires refused or ignored",
)
def get_diagnostics(request: Request) -> dict[str, dict[str, int]]:
    """Per dialect, counters of malformed or refused input (garbage on a serial line, unknown
    commands, commands ignored in the robot's state, Modbus exception answers, bad datagrams),
    since start: what a log would show, counted. Empty for dialects that count nothing."""
    return {name: read() for name, read in request.app.state.diagnostics.items()}
