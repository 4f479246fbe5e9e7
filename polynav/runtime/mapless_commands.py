"""Navigation without a map in the runtime: a NAVIGATING mode whose frame is odometry's.

A part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` by subject (it is one class to
its callers). :meth:`MaplessCommands.start_mapless` enters NAVIGATING (through BUSY, as starting
navigation on a map does) with a :class:`~polynav.nav.mapless.MaplessStack`: no map is loaded,
the current "map" is :data:`MAPLESS_FRAME`, goals are poses in the odometry frame sent through
the same goal command (``go_to(pose=...)``, ``POST /api/navigation/goal``), and the navigation
events, status, pause, cancel and ``stop_navigation`` are those of navigation on a map. Named
points belong to maps, so a point goal is refused (404) while mapless.
"""

from __future__ import annotations

import abc
import logging

from polynav.errors import Conflict
from polynav.nav.events import NavigationEvent
from polynav.nav.mapless import MaplessStack
from polynav.nav.stack import NavigationStack, StackConfig
from polynav.runtime import events
from polynav.runtime.config import Mode
from polynav.runtime.internals import RuntimeParts

log = logging.getLogger(__name__)

MAPLESS_FRAME = "odom"
"""The name the runtime gives the frame of mapless navigation where a map name would be."""


class MaplessCommands(RuntimeParts):
    @property
    def mapless(self) -> bool:
        """Whether navigation runs without a map (goals in the odometry frame)."""
        return self._mapless and self._mode is Mode.NAVIGATING

    def start_mapless(self) -> None:
        """Navigate with no map, from where the robot stands: goals are then poses in the
        odometry frame. Starting again (or from navigation on a map) cancels any goal.

        Raises:
            Conflict: MAPPING, or BUSY.
        """
        self._call(self._start_mapless)

    def _start_mapless(self) -> None:
        if self._mode is Mode.MAPPING:
            raise Conflict("mapping is running: stop it before navigating")
        if self._mode is Mode.BUSY:
            raise Conflict("the robot is busy")
        self.tasks.engine.give_way("cancelled: mapless navigation was started")
        self._cancel_goal()
        self._halt_motion()
        self._set_mode(Mode.BUSY)
        self._attempts.new_session()
        self._map_name = MAPLESS_FRAME
        self._grid = None
        self._keepouts = ()
        self._mapless = True
        stack = self._new_stack()
        self._stack = stack
        self._settings_dirty = False
        now = self.now()
        pose = self._robot.read_odometry().pose
        log.info("mapless navigation started at %s (odometry frame)", pose)
        self._publish(events.PoseInitialized(now, pose))
        self._set_mode(Mode.NAVIGATING)

    def _new_mapless_stack(self, config: StackConfig) -> NavigationStack:
        """The stack of mapless navigation (the runtime's ``_new_stack`` calls this)."""
        return MaplessStack(self._robot, config=config, on_event=self._on_nav_event)

    @abc.abstractmethod
    def _new_stack(self) -> NavigationStack:
        """A navigation stack with the current settings (mapless while ``_mapless``)."""

    @abc.abstractmethod
    def _on_nav_event(self, event: NavigationEvent) -> None:
        """Navigator events become runtime events."""
