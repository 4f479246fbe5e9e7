"""MovingAI grid maps (``.map``) and scenario files (``.scen``): the planners' reference data.

The MovingAI benchmarks (Sturtevant, "Benchmarks for Grid-Based Pathfinding", IEEE TCIAIG 2012;
Stern et al., SoCS 2019) give each map a list of start/goal queries with the optimal 8-connected,
no-corner-cutting path length. The planner tests and ``benchmarks/planner.py`` check polynav's A*
against those lengths.

Two orientations meet here. :func:`load_grid` keeps MovingAI's own: ``grid[row, col]`` with row 0
the *first* text line, which is what the scenario coordinates (x = column, y = row) index.
:func:`load_map` turns the same grid into a polynav :class:`~polynav.maps.map.Map`, whose row
``iy = 0`` is the *bottom* line (ROS), so ``iy = H - 1 - row``.

The files in the wild have quirks (``data/README.md``): only ``.`` is free; a header height
can be wrong, so rows are counted, not trusted; the last line may lack its newline; column 2 of a
scenario may be an absolute path from someone's machine; and toy files carry 0.0 placeholders
instead of optimal lengths (see :attr:`Scenario.has_reference_length`).
"""

from __future__ import annotations

import logging
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

from polynav.maps.errors import MapFormatError
from polynav.maps.map import FREE, OCCUPIED, Map, MapInfo

log = logging.getLogger(__name__)

_FREE_CHAR = "."


@dataclass(frozen=True, slots=True)
class Scenario:
    """One start/goal query of a ``.scen`` file, in MovingAI cell coordinates.

    ``x`` is the column and ``y`` the row counted from the *first* map line, so a query indexes
    :func:`load_grid`'s array as ``grid[y, x]``. ``optimal_length`` is in cells (orthogonal step
    1, diagonal sqrt 2).
    """

    bucket: int
    map_name: str
    width: int
    height: int
    start_x: int
    start_y: int
    goal_x: int
    goal_y: int
    optimal_length: float

    @property
    def has_reference_length(self) -> bool:
        """True when ``optimal_length`` is a real optimum, not a toy file's 0.0 placeholder.

        A length of 0 is only genuine when start and goal are the same cell.
        """
        same = self.start_x == self.goal_x and self.start_y == self.goal_y
        return self.optimal_length > 0.0 or same


def load_grid(path: str | os.PathLike[str]) -> npt.NDArray[np.bool_]:
    """Read a ``.map`` file as a blocked-cell grid in MovingAI orientation.

    Args:
        path: the ``.map`` file.

    Returns:
        ``grid[row, col]``, True where the cell is blocked (anything but ``.``), row 0 being the
        first map line. The height is the number of rows present, not the header's figure,
        because some files (``tree.map``, ``tree2.map``) state it wrongly.

    Raises:
        MapFormatError: missing file, no ``map`` line, no rows, or a row whose length differs
            from the header width.
    """
    file = Path(path)
    try:
        text = file.read_text(encoding="ascii")
    except (OSError, UnicodeDecodeError) as exc:
        raise MapFormatError("map", f"cannot read {file}: {exc}") from exc
    lines = text.splitlines()
    header: dict[str, str] = {}
    body_start = None
    for n, line in enumerate(lines):
        words = line.split()
        if not words:
            continue
        if words[0] == "map":
            body_start = n + 1
            break
        if len(words) == 2:
            header[words[0]] = words[1]
    if body_start is None:
        raise MapFormatError("map", f"{file}: no 'map' line")
    rows = [line.rstrip() for line in lines[body_start:]]
    while rows and not rows[-1]:
        rows.pop()
    if not rows:
        raise MapFormatError("map", f"{file}: no map rows")
    width = _header_int(header, "width", file, default=len(rows[0]))
    declared_height = _header_int(header, "height", file, default=len(rows))
    if declared_height != len(rows):
        log.debug("%s: header says height %d, %d rows present", file, declared_height, len(rows))
    for n, row in enumerate(rows):
        if len(row) != width:
            raise MapFormatError("map", f"{file}: row {n} has {len(row)} cells, expected {width}")
    chars = np.frombuffer("".join(rows).encode("ascii"), dtype=np.uint8)
    blocked: npt.NDArray[np.bool_] = (chars != ord(_FREE_CHAR)).reshape(len(rows), width)
    return blocked


def load_map(path: str | os.PathLike[str], resolution: float = 1.0) -> Map:
    """Read a ``.map`` file as a polynav :class:`Map` (occupied 100, free 0, origin at 0).

    Args:
        path: the ``.map`` file.
        resolution: cell size [m] to give the map; MovingAI maps have none of their own.

    Returns:
        The map, ``data[iy, ix]`` with ``iy = H - 1 - row``: the first map line is the top row.

    Raises:
        MapFormatError: as :func:`load_grid`, or a non-positive resolution.
    """
    if not resolution > 0.0:
        raise MapFormatError("resolution", f"must be > 0, got {resolution}")
    blocked = load_grid(path)
    data = np.where(blocked[::-1], OCCUPIED, FREE).astype(np.int8)
    height, width = blocked.shape
    info = MapInfo(resolution=float(resolution), width=width, height=height)
    return Map(info, np.ascontiguousarray(data))


def load_scenarios(path: str | os.PathLike[str]) -> list[Scenario]:
    """Read every query of a ``.scen`` file (version 1, nine tab-separated columns).

    Column 2 is reduced to its base name, since some files hold an absolute path from the
    author's machine. Lines are returned in file order; nothing is filtered, so callers decide
    what to do with placeholder lengths (:attr:`Scenario.has_reference_length`).

    Raises:
        MapFormatError: missing file or a line that does not have nine well-formed columns.
    """
    file = Path(path)
    try:
        text = file.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise MapFormatError("scen", f"cannot read {file}: {exc}") from exc
    scenarios: list[Scenario] = []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.startswith("version"):
            continue
        cols = line.rstrip("\r\n").split("\t")
        if len(cols) != 9:
            raise MapFormatError("scen", f"{file}:{number}: {len(cols)} columns, expected 9")
        try:
            scenarios.append(
                Scenario(
                    bucket=int(cols[0]),
                    map_name=_base_name(cols[1]),
                    width=int(cols[2]),
                    height=int(cols[3]),
                    start_x=int(cols[4]),
                    start_y=int(cols[5]),
                    goal_x=int(cols[6]),
                    goal_y=int(cols[7]),
                    optimal_length=float(cols[8]),
                )
            )
        except ValueError as exc:
            raise MapFormatError("scen", f"{file}:{number}: {exc}") from exc
    return scenarios


def _base_name(name: str) -> str:
    # Split on both separators: a path written on Windows must reduce the same way on Linux.
    return name.strip().replace("\\", "/").rsplit("/", 1)[-1]


def _header_int(header: dict[str, str], key: str, file: Path, *, default: int) -> int:
    if key not in header:
        return default
    try:
        return int(header[key])
    except ValueError as exc:
        raise MapFormatError("map", f"{file}: header {key} {header[key]!r}") from exc
