"""The fleet API's FastAPI application: a factory around one fleet manager (STYLE R5)."""

from __future__ import annotations

from dataclasses import dataclass

from fastapi import FastAPI
from fastapi.routing import APIRoute

from polynav.errors import ConfigError
from polynav.fleet.manager import FleetManager
from polynav.fleet_api.errors import ErrorOut, install_error_handlers
from polynav.fleet_api.routes import missions, records, robots, ws

ROUTERS = (robots, missions, records, ws)


@dataclass(frozen=True, slots=True)
class FleetApiConfig:
    """Where the fleet API listens, and how often its stream sends the robots.

    Attributes:
        host: the address to bind; loopback unless set otherwise.
        port: the TCP port (0: any free one).
        robots_period: between two robot lists on the WebSocket [s of wall time].
    """

    host: str = "127.0.0.1"
    port: int = 8090
    robots_period: float = 1.0

    def __post_init__(self) -> None:
        if not 0 <= self.port <= 65535:
            raise ConfigError("fleet_api.port", f"must be in [0, 65535], got {self.port}")
        if not self.robots_period > 0:
            raise ConfigError("fleet_api.robots_period",
                              f"must be > 0, got {self.robots_period}")


def _operation_id(route: APIRoute) -> str:
    """Stable OpenAPI operation ids: the route function's name."""
    return route.name


def create_app(manager: FleetManager, config: FleetApiConfig | None = None) -> FastAPI:
    """The fleet API around ``manager`` (ticked by its caller: the app never owns its
    lifetime)."""
    config = config or FleetApiConfig()
    app = FastAPI(title="polynav fleet manager", version="1",
                  description="Robots, missions, leases and audit of a polynav fleet "
                              "(VDA 5050 vehicles over MQTT).",
                  generate_unique_id_function=_operation_id,
                  responses={500: {"model": ErrorOut, "description": "a fault of the server"}})
    app.state.manager = manager
    app.state.robots_period = config.robots_period
    for module in ROUTERS:
        app.include_router(module.router)
    install_error_handlers(app)
    return app
