"""Maps written as ASCII art: the quickest way to state a small map in a test or an example.

``#`` is occupied, ``.`` is free and ``?`` is unknown. The first text line is the *top* row of the
map, as it reads on screen, so it becomes the highest ``iy`` (ROS maps keep ``iy = 0`` at the
bottom). :func:`map_to_ascii` is the inverse, handy in assertion messages.
"""

from __future__ import annotations

import logging
import textwrap

import numpy as np

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps.map import FREE, OCCUPIED, UNKNOWN, Map, MapInfo

log = logging.getLogger(__name__)

_VALUES = {"#": OCCUPIED, ".": FREE, "?": UNKNOWN}
_ORIGIN = Pose2D()  # frozen, so one shared default is safe


def map_from_ascii(text: str, resolution: float = 1.0, origin: Pose2D = _ORIGIN) -> Map:
    """Build a :class:`Map` from rows of ``#`` (occupied), ``.`` (free) and ``?`` (unknown).

    Blank lines and the common indentation are ignored, so a triple-quoted block can be written
    indented in place. The first non-blank line is the top row of the map.

    Args:
        text: the rows, all of the same length.
        resolution: cell size [m].
        origin: world pose of the lower-left corner of the bottom-left cell.

    Returns:
        The map, ``data[iy, ix]`` with ``iy = 0`` the last text line.

    Raises:
        InvalidRequest: rows of different lengths, an unknown character, no rows, or a
            non-positive resolution.
    """
    if not resolution > 0.0:
        raise InvalidRequest("resolution", f"must be > 0, got {resolution}")
    rows = [line.strip() for line in textwrap.dedent(text).splitlines()]
    rows = [row for row in rows if row]
    if not rows:
        raise InvalidRequest("text", "no map rows")
    width = len(rows[0])
    data = np.empty((len(rows), width), dtype=np.int8)
    for n, row in enumerate(rows):
        if len(row) != width:
            raise InvalidRequest("text", f"row {n} has {len(row)} cells, the first has {width}")
        for ix, char in enumerate(row):
            value = _VALUES.get(char)
            if value is None:
                raise InvalidRequest("text", f"row {n} column {ix}: unknown character {char!r}")
            data[n, ix] = value
    info = MapInfo(resolution=float(resolution), width=width, height=len(rows), origin=origin)
    return Map(info, np.ascontiguousarray(data[::-1]))


def map_to_ascii(grid: Map) -> str:
    """The map as ASCII rows, top row first; partly occupied cells (1..99) print as ``+``."""
    lines = []
    for iy in range(grid.info.height - 1, -1, -1):
        chars = []
        for value in grid.data[iy]:
            v = int(value)
            if v == UNKNOWN or v < 0 or v > OCCUPIED:
                chars.append("?")
            elif v == OCCUPIED:
                chars.append("#")
            elif v == FREE:
                chars.append(".")
            else:
                chars.append("+")
        lines.append("".join(chars))
    return "\n".join(lines)
