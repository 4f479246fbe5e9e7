"""Every Galileo HTTP endpoint, gathered from the route modules: add a module by one line.

Each module in :data:`MODULES` exposes ``ROUTES`` (a
:class:`~polynav.protocols.galileo.endpoint.RouteList`). :func:`table` checks that no method +
path is declared twice.
"""

from __future__ import annotations

from collections.abc import Iterable
from types import ModuleType

from polynav.protocols.galileo import (
    areas,
    auth,
    automations,
    charge,
    connections,
    coverage,
    fs,
    goals,
    local_moves,
    loop,
    map_files,
    mapping,
    navigation,
    paths,
    sensors,
    status,
    system_actuators,
    system_calibration,
    system_config,
    system_info,
    system_io,
    system_media,
    system_network,
    system_onvif,
    system_voice,
    tasks,
)
from polynav.protocols.galileo.endpoint import Endpoint, RouteList

MODULES: tuple[ModuleType, ...] = (
    auth,
    status,
    tasks,
    automations,
    navigation,
    goals,
    paths,
    areas,
    charge,
    loop,
    local_moves,
    mapping,
    map_files,
    coverage,
    sensors,
    connections,
    system_info,
    system_calibration,
    system_io,
    system_voice,
    system_media,
    system_actuators,
    system_network,
    system_config,
    system_onvif,
    fs,
)


def endpoints(modules: Iterable[ModuleType] = MODULES) -> list[Endpoint]:
    """Every endpoint of ``modules``, in order."""
    out: list[Endpoint] = []
    for module in modules:
        routes: RouteList = module.ROUTES
        out.extend(routes)
    return out


def table(modules: Iterable[ModuleType] = MODULES) -> dict[tuple[str, str], Endpoint]:
    """(method, path) -> endpoint.

    Raises:
        ValueError: two modules declare the same method and path.
    """
    out: dict[tuple[str, str], Endpoint] = {}
    for endpoint in endpoints(modules):
        key = (endpoint.method, endpoint.path)
        if key in out:
            raise ValueError(f"galileo: {endpoint.method} {endpoint.path} declared twice")
        out[key] = endpoint
    return out
