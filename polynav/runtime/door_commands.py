"""The building's doors and gates as a runtime part: reading them and an operator's hand on them.

A part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` by subject. Robots open the doors
on their way themselves (:mod:`polynav.runtime.door_passage`); these are for people: see each
door's state, hold one open by hand (a delivery through it, a fire drill) and let it go again.
An operator holds a door as the requester :data:`~polynav.robot.door.OPERATOR`: a robot's
request and the operator's are counted apart, so neither closes the door on the other.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping

from polynav.errors import NotFound, look_up
from polynav.robot.door import OPERATOR, Door, DoorStatus
from polynav.robot.sim.door import SimDoor
from polynav.runtime.door_passage import DoorPassage
from polynav.runtime.door_status import DoorsView, doors_view
from polynav.runtime.internals import RuntimeParts

log = logging.getLogger(__name__)


class DoorCommands(RuntimeParts):
    """The doors, read and opened by hand (see the module docstring)."""

    doors_rule: DoorPassage

    @property
    def doors(self) -> Mapping[str, Door]:
        """The building's doors and gates by name (the simulator's; a real site's controllers)."""
        return self._place.doors

    def door(self, name: str) -> Door:
        """Door ``name``.

        Raises:
            NotFound: no such door.
        """
        return look_up(self.doors, "door", name)

    def door_states(self) -> list[DoorStatus]:
        """Every door's state, by name."""
        return [door.state() for _, door in sorted(self.doors.items())]

    def _doors_view(self) -> DoorsView:
        """The doors as the status shows them: the rule's door waited at and doors held, and
        the robot's floor's doors."""
        rule = getattr(self, "doors_rule", None)
        waiting, held = (None, ()) if rule is None else (rule.waiting_for, rule.held)
        return doors_view(self.doors, self._place.floor, waiting, held)

    def open_door(self, name: str) -> DoorStatus:
        """Hold door ``name`` open by hand until :meth:`close_door` (between ticks).

        Raises:
            NotFound: no such door.
        """
        door = self.door(name)
        self._call(lambda: door.open(OPERATOR))
        log.info("door %s held open by the operator", name)
        return door.state()

    def close_door(self, name: str) -> DoorStatus:
        """Let go of door ``name`` by hand: it closes unless a robot still holds it.

        Raises:
            NotFound: no such door.
        """
        door = self.door(name)
        self._call(lambda: door.close(OPERATOR))
        log.info("door %s let go by the operator", name)
        return door.state()

    def set_door_answering(self, name: str, answering: bool) -> None:
        """Make a simulated door's controller answer or fall silent (rehearsing a dead link).

        Raises:
            NotFound: no such door, or not a simulated one.
        """
        door = self.door(name)
        if not isinstance(door, SimDoor):
            raise NotFound("simulated door", name)
        self._call(lambda: door.set_answering(answering))

    def _door_attempt_id(self) -> int:
        """The runtime's id of the goal the doors are opened for (a route's, else the last
        attempt's)."""
        route = getattr(self, "_route", None)
        attempt_id = getattr(route, "attempt_id", None)
        if isinstance(attempt_id, int):
            return attempt_id
        return self._attempts.attempt_id or 0
