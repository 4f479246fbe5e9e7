"""Goals on another map: the actions that take the robot across the site's connections.

The multi-floor router is the lifts issue's; until it lands on main, a goal on a map other than
the one in use is refused with a clear error (``Conflict``), never half-run.
"""

from __future__ import annotations

import logging

from polynav.errors import Conflict, NotFound
from polynav.protocols.galileo.actions import Action
from polynav.protocols.galileo.context import Context

log = logging.getLogger(__name__)


def map_of_level(ctx: Context, level: int) -> str:
    """The map of the floor at ``level``.

    Raises:
        NotFound: no floor has that level.
    """
    for floor in ctx.store.floors():
        if floor.level == level:
            return floor.map_name
    raise NotFound("floor of level", str(level))


def actions_between(ctx: Context, from_map: str, to_map: str) -> list[Action]:
    """The actions that bring the robot from ``from_map`` onto ``to_map``.

    Raises:
        Conflict: no chain of connections joins the two maps.
    """
    raise Conflict(f"no connection leads from map {from_map!r} to map {to_map!r}")
