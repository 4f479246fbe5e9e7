"""The simulator's electronic door: a :class:`~polynav.robot.door.Door` stepped on the scene's
clock, whose leaf is part of the floor's ground truth while it is not fully open.

The door opens in ``open_time`` while anyone holds it and closes in ``close_time`` once no one
does and its passage is clear (no robot body or person within :data:`SAFETY_MARGIN` of the
leaf's segment: the safety beam of a real door). Until it stands fully open its leaf is drawn
into the floor's occupancy grid (a strip :data:`LEAF_THICKNESS` thick along the segment): the
lidar sees it and a body collides with it. Fully open, the cells are given back as they were.

:meth:`SimDoor.set_answering` rehearses a broken controller: one that does not answer keeps its
state and ignores requests, as a real controller behind a dead link would.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

import numpy as np
import numpy.typing as npt

from polynav.errors import InvalidRequest
from polynav.maps.map import MapInfo
from polynav.robot.door import DoorStatus
from polynav.robot.lift import DoorState
from polynav.worlds.world import WorldDoor

log = logging.getLogger(__name__)

LEAF_THICKNESS = 0.1
"""[m] how thick the leaf is drawn into the grid (two cells of a 5 cm map)."""

SAFETY_MARGIN = 0.1
"""[m] a body or person this close to the leaf's segment (beyond its own radius) keeps the door
from closing."""

_EPS = 1e-9

Occupants = Callable[[WorldDoor, float], bool]
"""Whether anything stands within the given margin [m] of the door's segment."""


class SimDoor:
    """One simulated door (see the module docstring).

    Args:
        spec: the door from the world file.
        occupied: the floor's ground truth ``[iy, ix]``, changed in place.
        info: its geometry.
        occupants: whether the passage is occupied (from the scene).
        now: the scene's clock.
    """

    def __init__(self, spec: WorldDoor, occupied: npt.NDArray[np.bool_], info: MapInfo,
                 occupants: Occupants, now: Callable[[], float]) -> None:
        self.spec = spec
        self._occupied = occupied
        self._occupants = occupants
        self._now = now
        self._progress = 0.0  # 0 closed .. 1 open
        self._holders: set[str] = set()
        self._answering = True
        self._cells = _leaf_cells(spec, info)
        self._under = occupied[self._cells].copy()
        self._drawn = False
        self._draw(True)
        # The last status reported: valid while its stamp is the clock's time and nothing it
        # shows changed since; open, close, set_answering and a step that moves the leaf drop it.
        self._status: DoorStatus | None = None

    # -- the Door interface ------------------------------------------------------------------

    @property
    def name(self) -> str:
        return self.spec.name

    def state(self) -> DoorStatus:
        now = self._now()
        status = self._status
        if status is None or status.stamp != now:
            status = DoorStatus(self.spec, self._state(), tuple(sorted(self._holders)),
                                self._answering, now)
            self._status = status
        return status

    def open(self, requester: str) -> None:
        if not requester:
            raise InvalidRequest("requester", "a door request names who asks")
        if not self._answering:
            log.debug("door %s: no answer to %s's open", self.name, requester)
            return
        if requester not in self._holders:
            log.info("door %s: held open for %s", self.name, requester)
        self._holders.add(requester)
        self._status = None

    def close(self, requester: str) -> None:
        if not self._answering:
            return
        if requester in self._holders:
            self._holders.discard(requester)
            self._status = None
            log.info("door %s: %s lets go%s", self.name, requester,
                     "" if self._holders else "; closing")

    # -- simulator controls ------------------------------------------------------------------

    @property
    def answering(self) -> bool:
        return self._answering

    def set_answering(self, answering: bool) -> None:
        """Make the controller answer requests or ignore them (a dead link)."""
        self._answering = answering
        self._status = None
        log.info("door %s: controller %s", self.name, "answers" if answering else "silent")

    @property
    def blocking(self) -> bool:
        """Whether the leaf is in the ground truth (not fully open)."""
        return self._drawn

    # -- stepping ----------------------------------------------------------------------------

    def step(self, h: float) -> None:
        """Advance ``h`` [s]: open while held, close once free and clear; redraw the leaf."""
        if not self._answering:
            return
        before = self._progress
        if self._holders:
            self._progress = min(1.0, self._progress + h / self.spec.open_time)
        elif self._progress > _EPS and not self._occupants(self.spec, SAFETY_MARGIN):
            self._progress = max(0.0, self._progress - h / self.spec.close_time)
        if self._progress != before:
            self._status = None
        self._draw(self._progress < 1.0 - _EPS)

    def _state(self) -> DoorState:
        if self._progress >= 1.0 - _EPS:
            return DoorState.OPEN if self._holders or not self._answering else DoorState.CLOSING
        if self._progress <= _EPS:
            return DoorState.OPENING if self._holders and self._answering else DoorState.CLOSED
        return DoorState.OPENING if self._holders else DoorState.CLOSING

    def _draw(self, leaf: bool) -> None:
        if leaf == self._drawn:
            return
        self._occupied[self._cells] = True if leaf else self._under
        self._drawn = leaf
        log.debug("door %s: leaf %s", self.name, "in" if leaf else "out")


Cells = tuple[npt.NDArray[np.intp], npt.NDArray[np.intp]]


def _leaf_cells(spec: WorldDoor, info: MapInfo) -> Cells:
    """The grid cells ``(iy, ix)`` whose centres lie within half the leaf's thickness of its
    segment (at least the cells the segment passes through)."""
    res = info.resolution
    half = max(LEAF_THICKNESS, res) / 2.0
    xs = (min(spec.x1, spec.x2) - half, max(spec.x1, spec.x2) + half)
    ys = (min(spec.y1, spec.y2) - half, max(spec.y1, spec.y2) + half)
    ix0, iy0 = info.world_to_cell(xs[0], ys[0])
    ix1, iy1 = info.world_to_cell(xs[1], ys[1])
    ix0, iy0 = max(ix0, 0), max(iy0, 0)
    ix1, iy1 = min(ix1, info.width - 1), min(iy1, info.height - 1)
    gy, gx = np.mgrid[iy0:iy1 + 1, ix0:ix1 + 1]
    cx = info.origin.x + (gx + 0.5) * res  # the origin has zero yaw (the scene checks)
    cy = info.origin.y + (gy + 0.5) * res
    ex, ey = spec.x2 - spec.x1, spec.y2 - spec.y1
    t = np.clip(((cx - spec.x1) * ex + (cy - spec.y1) * ey) / (ex * ex + ey * ey), 0.0, 1.0)
    d = np.hypot(cx - (spec.x1 + t * ex), cy - (spec.y1 + t * ey))
    near = d <= half + 0.5 * res * 0.999
    return gy[near], gx[near]
