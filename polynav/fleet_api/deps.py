"""The fleet API's dependencies, as ``Annotated`` aliases."""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, Request, WebSocket

from polynav.fleet.manager import FleetManager


def _manager(request: Request) -> FleetManager:
    manager: FleetManager = request.app.state.manager
    return manager


def _ws_manager(websocket: WebSocket) -> FleetManager:
    manager: FleetManager = websocket.app.state.manager
    return manager


ManagerDep = Annotated[FleetManager, Depends(_manager)]
WsManagerDep = Annotated[FleetManager, Depends(_ws_manager)]
