""""No entry" signs the robot's sign camera spots: a passage closed for as long as it drives on
this map.

Only some robots have a sign camera (:class:`~polynav.robot.interface.SignCamera`; the
simulator's from the profile's ``sign_camera``). While a goal runs, each sign seen for the first
time is put on the map where it stands, as a keepout disk of :data:`NO_ENTRY_RADIUS` (wide
enough to close a doorway or a corridor's width for a robot), on top of the site's keepouts.
The navigator's route ahead is then closed: it stops before it and plans again at once, round
it where another way exists, else the goal fails (no path). A new navigation stack (another
map, a restart) forgets the signs: seen again, they close the way again.
:class:`~polynav.runtime.events.NoEntrySignSeen` tells each new sign to the dialects.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable

from polynav.maps.keepout import CircleZone, Keepout
from polynav.nav.attempt import NavigationState
from polynav.nav.stack import NavigationStack
from polynav.robot.interface import Robot, SignCamera
from polynav.runtime import events

log = logging.getLogger(__name__)

NO_ENTRY_RADIUS = 0.8  # [m] about a sign: the way it stands in is closed
SAME_SIGN = 0.5  # [m] a sign seen within this of one known is that one


class NoEntrySigns:
    """The signs seen on the current stack's map, and the keepouts they add."""

    def __init__(self, robot: Robot, publish: Callable[[events.RuntimeEvent], None],
                 site_keepouts: Callable[[], tuple[Keepout, ...]]) -> None:
        self._camera = robot if isinstance(robot, SignCamera) else None
        self._publish = publish
        self._site_keepouts = site_keepouts
        self._stack: NavigationStack | None = None
        self._signs: list[CircleZone] = []

    @property
    def signs(self) -> tuple[CircleZone, ...]:
        """The no-entry disks put on the current map."""
        return tuple(self._signs)

    def tick(self, now: float, stack: NavigationStack | None, attempt_id: int | None) -> None:
        """Look for signs while a goal runs; close the way at each new one."""
        if stack is not self._stack:
            self._stack, self._signs = stack, []
        if (self._camera is None or stack is None or attempt_id is None
                or stack.navigator.state is not NavigationState.RUNNING):
            return
        pose = stack.estimate.pose
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        added = []
        for seen in self._camera.read_signs():
            x, y = pose.x + c * seen.x - s * seen.y, pose.y + s * seen.x + c * seen.y
            if any(math.hypot(x - z.x, y - z.y) < SAME_SIGN for z in self._signs):
                continue
            zone = CircleZone(x, y, NO_ENTRY_RADIUS)
            self._signs.append(zone)
            added.append(zone)
        if not added:
            return
        stack.costmap.set_keepouts(self._site_keepouts() + tuple(self._signs))
        for zone in added:
            log.warning("no entry sign at (%.2f, %.2f): the way is closed", zone.x, zone.y)
            self._publish(events.NoEntrySignSeen(now, attempt_id, zone.x, zone.y))
