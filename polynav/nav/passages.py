"""Passages found closed during one goal: remembered, so the next plan goes round them.

The controller checks the real body against what the lidar marked; the planner plans on costs.
When the two disagree (a post the map does not have in a gap, a gap the planner's model of the
body thought wide enough, the lidar's marks cleared by a recovery a moment before the re-plan),
the robot stops before the passage, recovers, and the re-plan sends it into the same passage
again: four times, and the goal fails ``stuck`` while a way round was free all along.

So when the controller reports a block by the static or marked world (not by a person: people
walk on, :mod:`~polynav.nav.people_wait`), the passage is *closed for this goal*: the place where
the body first touched something along the route ahead (:meth:`ClosedPassages.close`). Every
plan then runs on a copy of the costmap where a disc of the body's inscribed radius there is
LETHAL (:meth:`ClosedPassages.planning_grid`): the body may not overlap it, so the route goes
round. A closure is forgotten when the goal ends, or when the cells that closed it, and those
within ``reopen_margin`` of them, have been seen free for ``reopen_after`` seconds (the lidar
sees the passage wider than thought: a trolley moved away); marks a recovery cleared come back
with the next scan, well within that time. The margin is there because a thin post's mark
wanders: without a map the lidar marks a 2 cm post in one cell or its neighbour from scan to
scan, so the one cell the body touched went free while the post stood, the closure was
forgotten and the next plan took the same gap (demo, lattice course 41 without a map: seven
closures of one place, timed out).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from polynav import footprint as body
from polynav.control.tracked_path import TrackedPath
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.costmap import Costmap, CostSnapshot
from polynav.maps.interface import CostGrid
from polynav.planning.path import Path

log = logging.getLogger(__name__)

LOOK_AHEAD = 2.5
"""How far along the route [m] the place that blocked the robot is looked for, by default: at
least as far as the controller stops before an obstacle (``NavigatorConfig.passage_look_ahead``;
a 2 m/s base stops 3 m before one, and a touch beyond 2.5 m went unnoted)."""


@dataclass(slots=True)
class ClosedPassage:
    """One closed passage: where the body would have touched, and the cells it touched."""

    x: float
    y: float
    radius: float
    cells: npt.NDArray[np.int64]
    watched: npt.NDArray[np.int64] | None = None
    free_since: float | None = None

    @property
    def name(self) -> str:
        return f"({self.x:.2f}, {self.y:.2f})"


@dataclass(frozen=True, slots=True)
class Touch:
    """Where the body, driving a route, first touches a LETHAL cell: the pose there and how far
    [m] along the route from the robot's place."""

    pose: Pose2D
    ahead: float


def first_touch(
    footprint: Footprint,
    costmap: CostGrid,
    route: TrackedPath,
    along: float,
    pose: Pose2D,
    look_ahead: float,
) -> Touch | None:
    """The first place within ``look_ahead`` [m] of ``along`` where the body following
    ``route`` from ``pose`` touches a LETHAL cell it does not touch where it stands, or
    ``None``."""
    res = costmap.info.resolution
    s = np.arange(along, min(route.length, along + look_ahead) + 0.5 * res, 0.5 * res)
    s = np.minimum(s, route.length)
    poses = route.poses_at(s)
    # The robot's own place first, so that what it touches already does not count.
    poses = np.vstack([[pose.x, pose.y, pose.theta], poses])
    hit = body.first_collision(footprint, costmap, poses, ignore_start=True)
    if hit is None:
        return None
    x, y, theta = (float(v) for v in poses[hit])
    return Touch(Pose2D(x, y, theta), float(s[max(hit - 1, 0)]) - along)


@dataclass
class ClosedPassages:
    """The passages closed in one navigation attempt (module docstring).

    Args:
        footprint: the body.
        limit: at most this many closures per goal; blocks beyond it count as plain failures.
        reopen_after: a closure whose cells stay free this long [s] is forgotten.
        reopen_margin: a closure is free only when no cell within this distance [m] of the
            cells that closed it is marked either (a thin post's mark wanders by a cell).
        time_budget: no passage is closed later than this [s] after the first closure of the
            goal (``NavigatorConfig.passage_time_budget``).
        look_ahead: how far along the route [m] a block's place is looked for.
    """

    footprint: Footprint
    time_budget: float
    limit: int = 12
    look_ahead: float = LOOK_AHEAD
    reopen_after: float = 2.0
    reopen_margin: float = 0.1
    passages: list[ClosedPassage] = field(default_factory=list)
    tried: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        self._noted: ClosedPassage | None = None
        self.noted_touch: Touch | None = None
        """Where the body touched along the route at the last block (:meth:`note_block`)."""
        self._first: float | None = None

    def reset(self) -> None:
        """A new goal: nothing is closed."""
        self.passages.clear()
        self.tried.clear()
        self._noted = None
        self.noted_touch = None
        self._first = None

    def reopen_all(self) -> None:
        """Forget every closure (their names stay in ``tried``): when they leave no way at all,
        the block may have been something that moves on (another robot, a trolley)."""
        self.passages.clear()

    @property
    def full(self) -> bool:
        return len(self.passages) >= self.limit

    def note_block(
        self, costmap: CostGrid, route: TrackedPath | None, along: float, pose: Pose2D
    ) -> None:
        """The controller has just stopped: note where the body touches something along the
        route ahead of ``along`` [m], as the costmap is now (a thin post's mark may flicker
        out before the navigator decides what to do about the block)."""
        self._noted = None
        self.noted_touch = None
        if route is None:
            return
        touch = first_touch(self.footprint, costmap, route, along, pose, self.look_ahead)
        if touch is not None:
            cells = body.overlapped_cells(self.footprint, costmap, touch.pose)
            watched = _dilated(costmap, cells, self.reopen_margin)
            self._noted = ClosedPassage(touch.pose.x, touch.pose.y,
                                        self.footprint.inscribed_radius, cells, watched)
            self.noted_touch = touch

    def close(self, now: float) -> ClosedPassage | None:
        """Close the passage noted at the last block; ``None`` when the body touched nothing
        along the route then (the block was the arc or a turn), the place is closed already,
        or the limit or the time budget is spent."""
        passage, self._noted = self._noted, None
        if passage is None or self.full:
            return None
        if self._first is not None and now - self._first > self.time_budget:
            return None
        for known in self.passages:
            if math.hypot(known.x - passage.x, known.y - passage.y) < passage.radius:
                return None
        self.passages.append(passage)
        self.tried.append(passage.name)
        if self._first is None:
            self._first = now
        log.info("passage at %s closed for this goal (%d cells)", passage.name,
                 passage.cells.shape[0])
        return passage

    def refresh(self, costmap: CostGrid, now: float) -> None:
        """Forget closures whose cells the lidar has seen free for ``reopen_after``."""
        kept = []
        grid = costmap.costs
        for passage in self.passages:
            cells = passage.cells if passage.watched is None else passage.watched
            marked = cells.shape[0] == 0 or bool(
                np.any(grid[cells[:, 1], cells[:, 0]] == costs.LETHAL)
            )
            if marked:
                passage.free_since = None
            elif passage.free_since is None:
                passage.free_since = now
            elif now - passage.free_since >= self.reopen_after:
                log.info("passage at %s seen open again", passage.name)
                continue
            kept.append(passage)
        self.passages = kept

    def planning_grid(self, costmap: CostGrid, pose: Pose2D) -> CostGrid:
        """``costmap``, or a copy with every closure painted LETHAL (except within the body's
        reach of where it stands, so that the robot may turn and leave)."""
        if not self.passages:
            return costmap
        info = costmap.info
        grid = np.array(costmap.costs, dtype=np.uint8, copy=True)
        cells = np.zeros((0, 2), dtype=np.int64)
        for passage in self.passages:
            cells = np.vstack([cells, info.cells_within(passage.x, passage.y, passage.radius)])
        if cells.shape[0]:
            mask = np.zeros(grid.shape, dtype=bool)
            mask[cells[:, 1], cells[:, 0]] = True
            reach = self.footprint.circumscribed_radius + info.resolution
            here = info.cells_within(pose.x, pose.y, reach)
            mask[here[:, 1], here[:, 0]] = False
            grid[mask] = costs.LETHAL
        return CostSnapshot(info, grid)


def open_doors_on(costmap: Costmap, path: Path) -> None:
    """Take off the body's costmap the shut doors ``path`` crosses
    (:meth:`~polynav.maps.costmap.Costmap.set_shut_doors`): the planner routed through them
    (:meth:`~polynav.maps.costmap.Costmap.planning_costs`), so the robot will open them on its
    way, and the door rule stops it before one not yet open. Left on until the door rule's
    next step, the leaf ahead stopped the controller, and the block closed that passage for the
    goal."""
    shut = costmap.shut_doors
    if not shut:
        return
    kept = [leaf for leaf in shut
            if not any(path.crosses(p, q) for p, q in zip(leaf.points, leaf.points[1:],
                                                          strict=False))]
    if len(kept) != len(shut):
        costmap.set_shut_doors(kept)


def touches_marks(costmap: Costmap, footprint: Footprint, pose: Pose2D) -> bool:
    """Does the body at ``pose`` touch a LETHAL cell the map does not have (a lidar mark: a
    person's trail, a trolley), rather than only the building?"""
    cells = body.overlapped_cells(footprint, costmap, pose)
    if cells.shape[0] == 0:
        return False
    centres = costmap.info.cells_to_world(cells)
    # Unknown in the map (no map at all: navigating without one) is not the building either.
    return any(costmap.map_cost_at(float(x), float(y)) != costs.LETHAL for x, y in centres)


def _dilated(
    costmap: CostGrid, cells: npt.NDArray[np.int64], margin: float
) -> npt.NDArray[np.int64]:
    """``cells`` and every cell of the grid within ``margin`` [m] (centre to centre) of one."""
    info = costmap.info
    reach = int(math.floor(margin / info.resolution + 1e-9))
    if reach <= 0 or cells.shape[0] == 0:
        return cells
    span = np.arange(-reach, reach + 1)
    dx, dy = np.meshgrid(span, span)
    near = np.hypot(dx, dy) <= reach + 1e-9
    offsets = np.column_stack((dx[near], dy[near])).astype(np.int64)
    grown = (cells[:, None, :] + offsets[None, :, :]).reshape(-1, 2)
    inside = (grown[:, 0] >= 0) & (grown[:, 1] >= 0) & (grown[:, 0] < info.width) & (
        grown[:, 1] < info.height)
    return np.asarray(np.unique(grown[inside], axis=0), dtype=np.int64)
