"""Every Puwei HTTP endpoint: each route module's list, gathered (a new module is one line)."""

from __future__ import annotations

from polynav.protocols.puwei import auth, devices, launch, maps, parameters, robot, tasks
from polynav.protocols.puwei.endpoint import Endpoint

MODULES = (devices, auth, launch, maps, parameters, tasks, robot)


def table() -> list[Endpoint]:
    """The endpoints of every route module, in order."""
    return [endpoint for module in MODULES for endpoint in module.ROUTES]
