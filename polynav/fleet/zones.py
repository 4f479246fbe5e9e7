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
(the room a robot coming out of the passage needs before it can pass a waiting one), is a
passage; passages closer than ``merge_gap`` are one, so a robot never stops for a door while it
stands in the narrow bit right before it. A passage longer than ``segment_length`` (a corridor
with its doors and side passages) is cut into segments, each a zone leased on its own: robots
in different stretches of a corridor go at once. A robot asks for every segment of the
passage on its way (a :class:`ZoneRun`), in ascending zone number, before it goes in
(:mod:`polynav.fleet.traffic`).

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

from polynav.errors import ConfigError, check_positive
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
        segment_length: a zone longer than this [m] is cut into segments no longer than it,
            each leased on its own (a corridor with its doors and side passages).
    """

    robot_radius: float = 0.25
    narrow_width: float = 2.1
    approach: float = 0.7
    merge_gap: float = 1.5
    segment_length: float = 8.0

    def __post_init__(self) -> None:
        check_positive(self, _KEY, ("robot_radius", "narrow_width", "approach", "merge_gap",
                                    "segment_length"))
        if self.narrow_width <= 2.0 * self.robot_radius:
            raise ConfigError(_KEY + "narrow_width", "must be wider than one robot")
        if self.segment_length < 2.0 * self.merge_gap:
            raise ConfigError(_KEY + "segment_length",
                              f"must be at least twice merge_gap ({2.0 * self.merge_gap})")


@dataclass(frozen=True, slots=True)
class ZoneRun:
    """One stretch of a path through one zone group (a passage and the segments it was cut
    into): the segments in the order the path enters them.

    Attributes:
        group: the group's number.
        entry: how far along the path it starts [m]; 0 when the robot stands in it.
        segments: the segment numbers, each once, in the order the path enters them.
        entries: how far along the path each of them starts [m].
    """

    group: int
    entry: float
    segments: tuple[int, ...]
    entries: tuple[float, ...]


@dataclass(frozen=True, slots=True, eq=False)
class ZoneMap:
    """The zones of one map: ``labels[iy, ix]`` is the zone number there (0: none).

    A zone is one lease: a short passage, or a segment of a long one (a corridor, with the
    doors and side passages along it); ``group_of[n]`` is the passage zone ``n`` is part of.

    Attributes:
        map_name: the map the zones belong to.
        grid: that map (for its frame).
        labels: zone number per cell, 0 outside every zone.
        count: how many zones there are (numbers 1..count).
        core: the narrow cells themselves, before the zones grew round them.
        group_of: the group (passage) number of each zone, indexed by zone number (0: none).
        rejoin: a path out of a group for less than this [m] is still on the same run
            through it (a doorway's landing between a side passage and the room's door).
    """

    map_name: str
    grid: Map
    labels: npt.NDArray[np.int32]
    count: int
    core: npt.NDArray[np.bool_]
    group_of: npt.NDArray[np.int32] | None = None
    rejoin: float = 1.5

    def group(self, number: int) -> int:
        """The group (passage) zone ``number`` is part of; 0 for 0."""
        if self.group_of is None:
            return number
        return int(self.group_of[number])

    def runs(self, path: Path, x: float, y: float, *, reach: float,
             skip_group: int = 0) -> list[ZoneRun]:
        """The runs of ``path``, from the point nearest to (x, y), through zone groups other
        than ``skip_group`` that start within ``reach`` [m] along it, in path order.

        A run goes on through the group's segments while the path stays in the group, or out
        of it for less than ``rejoin``; it ends at another group or a longer way out.
        """
        s, _, labels, _ = self._samples(path, x, y, math.inf)
        groups = self._groups(labels)
        step = 0.5 * self.grid.info.resolution
        gap_samples = max(1, int(math.ceil(self.rejoin / step)))
        # Whole arrays at a time: the path is sampled every half cell from the robot to its
        # end (thousands of samples across a building), of which a run is a short stretch.
        marked = np.flatnonzero(groups != 0)  # the samples in some zone, in path order
        marked_groups = groups[marked]
        starts = np.flatnonzero(marked_groups != skip_group)  # where a run may begin
        # Whether marked sample i + 1 goes on the run of sample i: the same group, and out of
        # it for at most gap_samples samples in between.
        goes_on = ((marked_groups[1:] == marked_groups[:-1])
                   & (np.diff(marked) <= gap_samples + 1))
        breaks = np.flatnonzero(~goes_on)  # the run of sample i ends at i when i is here
        out: list[ZoneRun] = []
        i, n = 0, marked.shape[0]
        while starts.shape[0] and i < n:
            i = int(starts[np.searchsorted(starts, i)]) if starts[-1] >= i else n
            if i >= n or s[marked[i]] > reach:
                break
            last = int(breaks[np.searchsorted(breaks, i)]) if breaks.shape[0] and (
                breaks[-1] >= i) else n - 1
            run = marked[i:last + 1]
            numbers, first = np.unique(labels[run], return_index=True)
            order = np.argsort(first)
            out.append(ZoneRun(int(marked_groups[i]), float(s[marked[i]]),
                               tuple(int(z) for z in numbers[order]),
                               tuple(float(e) for e in s[run[first[order]]])))
            i = last + 1
        return out

    def _groups(self, labels: npt.NDArray[np.int32]) -> npt.NDArray[np.int32]:
        return labels if self.group_of is None else self.group_of[labels]

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

    def zones_near(self, x: float, y: float, radius: float) -> frozenset[int]:
        """The zone numbers within ``radius`` [m] of world (x, y): the zones a body of that
        radius standing there is in, wholly or in part."""
        cells = self.grid.info.cells_within(x, y, radius)
        found = np.unique(self.labels[cells[:, 1], cells[:, 0]])
        return frozenset(int(n) for n in found if n != 0)

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
        edge heading away from the passage, not through it. Out of the zone's group, that is:
        into the next segment of a long passage is not out."""
        _, _, labels, core = self._samples(path, x, y, within)
        groups = self._groups(labels)
        out = np.flatnonzero(groups != self.group(zone))
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
    segments, group_of = _segments(labels, count, max(2, int(round(config.segment_length / res))),
                                   min_cells=max(1, int(round(1.0 / (res * res)))))
    log.info("map %s: %d traffic zones in %d passages", map_name, group_of.shape[0] - 1, count)
    return ZoneMap(map_name=map_name, grid=grid, labels=segments,
                   count=int(group_of.shape[0] - 1), core=narrow, group_of=group_of,
                   rejoin=config.merge_gap)


def _segments(labels: npt.NDArray[np.int32], count: int, longest: int, *, min_cells: int,
              ) -> tuple[npt.NDArray[np.int32], npt.NDArray[np.int32]]:
    """Cut each passage of ``labels`` (1..count) longer than ``longest`` cells into segments:
    the segment numbers per cell, and the passage of each segment (index 0: none).

    A passage is cut in two across its longer side, at the narrowest cross-section near its
    middle (in a corridor, between two side openings rather than through one), each side's
    connected parts cut again until none is longer than ``longest``; a part smaller than
    ``min_cells`` (a corner clipped by a cut) joins the segment it touches most.
    """
    out = np.zeros_like(labels)
    group_of = [0]
    square = np.ones((3, 3), dtype=bool)
    for number, box in enumerate(ndimage.find_objects(labels, max_label=count), start=1):
        if box is None:
            continue
        mask = labels[box] == number
        pieces = _cut(mask, longest)
        local = np.zeros(mask.shape, dtype=np.int32)
        for i, piece in enumerate(pieces, start=1):
            local[piece] = i
        _absorb_slivers(local, len(pieces), min_cells, square)
        used = [int(v) for v in np.unique(local) if v != 0]
        for v in used:
            group_of.append(number)
            out[box][local == v] = len(group_of) - 1
    return out, np.array(group_of, dtype=np.int32)


def _cut(mask: npt.NDArray[np.bool_], longest: int) -> list[npt.NDArray[np.bool_]]:
    """``mask`` in connected parts none longer than ``longest`` cells (see :func:`_segments`)."""
    ys, xs = np.nonzero(mask)
    if ys.shape[0] == 0:
        return []
    spans = (int(ys.max() - ys.min()) + 1, int(xs.max() - xs.min()) + 1)
    if max(spans) <= longest:
        return [mask]
    axis = 1 if spans[1] >= spans[0] else 0  # cut across the longer side
    lo = int(xs.min() if axis == 1 else ys.min())
    length = spans[axis]
    profile = mask.sum(axis=1 - axis)[lo:lo + length]
    middle = length // 2
    window = np.arange(max(1, middle - length // 4), min(length - 1, middle + length // 4) + 1)
    # The narrowest cross-section, nearest the middle among equals.
    best = window[np.lexsort((np.abs(window - middle), profile[window]))[0]]
    cut = lo + int(best)
    index = np.arange(mask.shape[axis])
    before = (index < cut)[None, :] if axis == 1 else (index < cut)[:, None]
    parts: list[npt.NDArray[np.bool_]] = []
    for side in (mask & before, mask & ~before):
        pieces, n = ndimage.label(side, structure=np.ones((3, 3), dtype=bool))
        for k in range(1, n + 1):
            parts.extend(_cut(pieces == k, longest))
    return parts


def _absorb_slivers(local: npt.NDArray[np.int32], n: int, min_cells: int,
                    square: npt.NDArray[np.bool_]) -> None:
    """Give each segment of ``local`` (1..n) smaller than ``min_cells`` to the neighbouring
    segment it shares the longest border with (in place)."""
    for v in range(1, n + 1):
        piece = local == v
        size = int(piece.sum())
        if size == 0 or size >= min_cells:
            continue
        rim = ndimage.binary_dilation(piece, structure=square) & ~piece
        neighbours = local[rim]
        neighbours = neighbours[(neighbours != 0) & (neighbours != v)]
        if neighbours.shape[0]:
            local[piece] = int(np.bincount(neighbours).argmax())


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
