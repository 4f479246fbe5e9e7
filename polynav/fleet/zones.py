"""Traffic zones: the narrow passages of a map, where two robots cannot pass each other.

A doorway, a lift door or a narrow corridor lets one robot through at a time; two that meet in
it head-on block each other for good (each sees the other as an obstacle and no path is left).
The fleet therefore makes each such passage a *zone*, leased to one robot at a time
(:mod:`polynav.leases.book`): a robot holds the zone's lease before it enters and gives it back
once it has left (the traffic rule, :mod:`polynav.fleet.traffic`).

Zones are found in the map itself, so a new map needs no drawing. A free cell is *narrow* when
the free run through it, along the map's rows or along its columns, is shorter than
``narrow_width``: a doorway in a wall is narrow across the wall and not along it; a corridor
wide enough for two robots is not narrow at all. Runs too short for one robot (``2 × radius``)
are no passage and are left out. Each connected group of narrow cells, grown by ``approach``
(the room a robot coming out of the passage needs before it can pass a waiting one), is a zone;
zones closer than ``merge_gap`` are one zone, so a robot never needs two leases at once to pass
a door and the narrow bit right behind it.

Robots that never head opposite ways in a zone never meet head-on in it, so they may share
it: the *flow* of a path through a zone is the compass sectors of its heading along the way,
every half metre from where it enters the zone to where it leaves it, each turn once
(``"EE"`` along a corridor eastwards, ``"NE"`` out of a door on its south side and east along
it, ``"NWS"`` up one side passage, west along the corridor and down another), and the lease
book lets holders in together whose flows hold no opposite sectors (:mod:`polynav.leases.book`).
The whole way counts: a robot coming out of a door and turning east (``"NE"``) and one coming
from the west to turn into that door (``"ES"``) both head east overall, yet meet in the door;
and two ways that enter and leave alike can still cross the corridor between them opposite
ways (up one passage and east, against up another and west, both ``"NN"`` by their ends alone:
on the demo's floor 2, 28 % of the pairs that equal ends let in together met head-on, issue
36). A way through shorter than half a metre (a robot turning round at a door) has no flow and
is asked for alone.

This finds passages along the map's axes, which is how buildings are drawn; a narrow passage at
45° to the grid is not found (a documented limit, docs/fleet.md).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from polynav.errors import ConfigError
from polynav.maps.map import Map
from polynav.planning.path import Path

log = logging.getLogger(__name__)

_KEY = "fleet.zones."

_FLOW_MIN = 0.5
"""A way through a zone shorter than this [m] has no clear direction (module docstring)."""


@dataclass(frozen=True, slots=True)
class ZoneConfig:
    """How narrow passages are found.

    Attributes:
        robot_radius: the robots' footprint radius [m].
        narrow_width: a free run shorter than this [m] is a passage for one robot only.
        approach: a zone reaches this far [m] beyond its narrow cells.
        merge_gap: zones whose regions come closer than this [m] are one zone.
    """

    robot_radius: float = 0.25
    narrow_width: float = 2.1
    approach: float = 0.7
    merge_gap: float = 1.5

    def __post_init__(self) -> None:
        for name in ("robot_radius", "narrow_width", "approach", "merge_gap"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ConfigError(_KEY + name, f"must be finite and > 0, got {value}")
        if self.narrow_width <= 2.0 * self.robot_radius:
            raise ConfigError(_KEY + "narrow_width", "must be wider than one robot")


@dataclass(frozen=True, slots=True, eq=False)
class ZoneMap:
    """The zones of one map: ``labels[iy, ix]`` is the zone number there (0: none).

    Attributes:
        map_name: the map the zones belong to.
        grid: that map (for its frame).
        labels: zone number per cell, 0 outside every zone.
        count: how many zones there are (numbers 1..count).
        core: the narrow cells themselves, before the zones grew round them.
    """

    map_name: str
    grid: Map
    labels: npt.NDArray[np.int32]
    count: int
    core: npt.NDArray[np.bool_]

    def zone_id(self, number: int) -> str:
        """The lease book's name of zone ``number``: ``zone:<map>/<number>``."""
        return f"zone:{self.map_name}/{number}"

    def zone_at(self, x: float, y: float) -> int:
        """The zone number at world (x, y) [m], 0 outside every zone or the map."""
        info = self.grid.info
        ix, iy = info.world_to_cell(x, y)
        if not info.contains(ix, iy):
            return 0
        return int(self.labels[iy, ix])

    def zone_ahead(self, path: Path, x: float, y: float, *, lookahead: float,
                   skip: int = 0) -> tuple[int, float] | None:
        """The first zone other than ``skip`` that ``path`` enters from the point nearest to
        (x, y), within ``lookahead`` [m] along it: (zone number, distance [m]) or None.

        The path is sampled every half cell, so a zone a cell wide is never stepped over.
        """
        s, _, labels, _ = self._samples(path, x, y, lookahead)
        hits = np.flatnonzero((labels != 0) & (labels != skip))
        if hits.shape[0] == 0:
            return None
        k = int(hits[0])
        return int(labels[k]), float(s[k])

    def leaves(self, path: Path, x: float, y: float, zone: int, *, within: float) -> bool:
        """Whether ``path``, from the point nearest to (x, y), is out of zone ``zone`` within
        ``within`` [m] along it without touching the zone's narrow core: a robot at the zone's
        edge heading away from the passage, not through it."""
        _, _, labels, core = self._samples(path, x, y, within)
        out = np.flatnonzero(labels != zone)
        return out.shape[0] > 0 and not bool(np.any(core[:out[0]]))

    def flow(self, path: Path, x: float, y: float, zone: int) -> str | None:
        """The way ``path``, from the point nearest to (x, y), goes through zone ``zone``: the
        compass sectors (``E``, ``N``, ``W``, ``S``, in the map's frame) of its heading where it
        enters the zone (or at (x, y), inside it), every ``_FLOW_MIN`` along it, and where it
        leaves it (or ends), a sector repeated only at the ends of a straight way, e.g.
        ``"NE"``: out of a door northwards, then east along the corridor; ``"EE"``: straight
        east. None when the path does not go through the zone or goes less than ``_FLOW_MIN``
        across it (no clear way: the robot asks for the zone alone)."""
        _, xy, labels, _ = self._samples(path, x, y, math.inf)
        inside = np.flatnonzero(labels == zone)
        if inside.shape[0] == 0:
            return None
        first = int(inside[0])
        gone = np.flatnonzero(labels[first:] != zone)
        last = first + int(gone[0]) - 1 if gone.shape[0] else labels.shape[0] - 1
        if math.hypot(*(xy[last] - xy[first])) < _FLOW_MIN:
            return None
        # The heading over each _FLOW_MIN of the way (samples every half cell), and over the
        # last one.
        k = max(1, int(round(_FLOW_MIN / (0.5 * self.grid.info.resolution))))
        steps = [xy[min(i + k, last)] - xy[i] for i in range(first, last - k + 1, k)]
        steps.append(xy[last] - xy[max(last - k, first)])
        sectors = [_sector(step) for step in steps if float(np.hypot(*step)) > 0.0]
        turns = "".join(c for i, c in enumerate(sectors) if i == 0 or c != sectors[i - 1])
        if not turns:
            return None
        return turns * 2 if len(turns) == 1 else turns

    def _samples(
        self, path: Path, x: float, y: float, reach: float,
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.int32],
               npt.NDArray[np.bool_]]:
        """Samples every half cell along ``path`` from (x, y) up to ``reach`` [m]: their arc
        lengths [m], points (M, 2), zone numbers, and whether each is in a zone's narrow core."""
        points = path.points
        if points.shape[0] == 0:
            return (np.zeros(0), np.zeros((0, 2)), np.zeros(0, dtype=np.int32),
                    np.zeros(0, dtype=bool))
        ahead = np.vstack(([x, y], _rest_of(points, x, y)))
        seg = np.hypot(*np.diff(ahead, axis=0).T)
        along = np.concatenate(([0.0], np.cumsum(seg)))
        # The points up to and including the first one at or past the reach.
        end = min(along.shape[0], int(np.searchsorted(along, reach, side="left")) + 1)
        step = 0.5 * self.grid.info.resolution
        last = min(reach, float(along[end - 1]))
        s = np.arange(0.0, last + step, step)
        s = s[s <= last]
        xs = np.interp(s, along[:end], ahead[:end, 0])
        ys = np.interp(s, along[:end], ahead[:end, 1])
        xy = np.column_stack((xs, ys))
        cells = self.grid.info.world_to_cells(xy)
        info = self.grid.info
        inside = ((cells[:, 0] >= 0) & (cells[:, 0] < info.width) & (cells[:, 1] >= 0)
                  & (cells[:, 1] < info.height))
        labels = np.zeros(s.shape[0], dtype=np.int32)
        labels[inside] = self.labels[cells[inside, 1], cells[inside, 0]]
        core = np.zeros(s.shape[0], dtype=bool)
        core[inside] = self.core[cells[inside, 1], cells[inside, 0]]
        return s, xy, labels, core


def _sector(direction: npt.NDArray[np.float64]) -> str:
    """The compass sector of ``direction`` (dx, dy): E, N, W or S."""
    angle = math.atan2(float(direction[1]), float(direction[0]))
    return "ENWS"[int(round(angle / (math.pi / 2))) % 4]


def _rest_of(points: npt.NDArray[np.float64], x: float, y: float) -> npt.NDArray[np.float64]:
    """The polyline ``points`` from the point on it nearest to (x, y) on (a sparse path's
    nearest *vertex* may lie behind the robot)."""
    if points.shape[0] == 1:
        return points
    a, b = points[:-1], points[1:]
    d = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-18)
    t = np.clip(((x - a[:, 0]) * d[:, 0] + (y - a[:, 1]) * d[:, 1]) / length2, 0.0, 1.0)
    foot = a + t[:, None] * d
    k = int(np.argmin((foot[:, 0] - x) ** 2 + (foot[:, 1] - y) ** 2))
    return np.vstack((foot[k], points[k + 1:]))


def find_zones(map_name: str, grid: Map, config: ZoneConfig | None = None) -> ZoneMap:
    """The narrow passages of ``grid`` as zones (see the module docstring)."""
    config = config or ZoneConfig()
    res = grid.info.resolution
    free = ~grid.occupied()
    rows = _run_lengths(free) * res
    cols = _run_lengths(free.T).T * res
    across = np.minimum(rows, cols)
    narrow = free & (across < config.narrow_width) & (across >= 2.0 * config.robot_radius)
    # A passage must also let the robot's centre through: cells nearer a wall than the radius
    # are only the passage's edges.
    # The world ends at the grid's edge: pad with walls, so the edge bounds the clearance.
    padded = np.pad(free, 1, constant_values=False)
    clearance = ndimage.distance_transform_edt(padded)[1:-1, 1:-1] * res
    narrow &= clearance > config.robot_radius
    # Grow through free space only: a zone never leaks through a wall into the next room.
    grow = max(1, int(round(config.approach / res)))
    merge = max(1, int(round(0.5 * config.merge_gap / res)))
    square = np.ones((3, 3), dtype=bool)
    grown = ndimage.binary_dilation(narrow, structure=square, iterations=grow + merge, mask=free)
    groups, count = ndimage.label(grown, structure=square)
    # Shrink back by the merge margin, keeping the group numbers: groups joined by the margin
    # stay one zone.
    region = ndimage.binary_dilation(narrow, structure=square, iterations=grow, mask=free)
    labels = np.where(region, groups, 0).astype(np.int32)
    labels, count = _renumber(labels)
    log.info("map %s: %d traffic zones", map_name, count)
    return ZoneMap(map_name=map_name, grid=grid, labels=labels, count=count, core=narrow)


def _run_lengths(free: npt.NDArray[np.bool_]) -> npt.NDArray[np.float64]:
    """For each cell, the length (in cells) of the run of free cells along its row that holds
    it; 0 on occupied cells."""
    h, w = free.shape
    out = np.zeros((h, w), dtype=np.float64)
    padded = np.zeros((h, w + 2), dtype=np.int8)
    padded[:, 1:-1] = free
    edges = np.diff(padded, axis=1)
    for iy in range(h):
        starts = np.flatnonzero(edges[iy] == 1)
        ends = np.flatnonzero(edges[iy] == -1)
        for a, b in zip(starts, ends, strict=True):
            out[iy, a:b] = b - a
    return out


def _renumber(labels: npt.NDArray[np.int32]) -> tuple[npt.NDArray[np.int32], int]:
    used = np.unique(labels)
    used = used[used != 0]
    table = np.zeros(int(labels.max()) + 1, dtype=np.int32)
    table[used] = np.arange(1, used.shape[0] + 1, dtype=np.int32)
    return table[labels], int(used.shape[0])
