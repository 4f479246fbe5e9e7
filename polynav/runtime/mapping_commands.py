"""Mapping commands of the runtime: start a map, watch it grow, save it, stop, cancel.

A part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` by subject (it is one class
to its callers); what it shares with the others is declared in
:class:`~polynav.runtime.internals.RuntimeParts`. MAPPING is entered from FREE only; the robot
is driven by teleop (or local moves) meanwhile, and :meth:`stop_mapping` saves before it stops,
as the vendors document.
"""

from __future__ import annotations

import logging

from polynav.errors import Conflict, NotFound
from polynav.geometry import Pose2D
from polynav.maps.map import Map
from polynav.runtime.config import Mode
from polynav.runtime.exploration import Exploration
from polynav.runtime.internals import RuntimeParts
from polynav.runtime.mapping_session import MappingSession

log = logging.getLogger(__name__)


class MappingCommands(RuntimeParts):
    def start_mapping(self) -> None:
        """Start a new map where the robot stands: its pose now is the new map's frame.

        Raises:
            Conflict: not FREE (navigating: stop navigation first; already mapping; busy).
        """

        def run() -> None:
            if self._mode is Mode.MAPPING:
                raise Conflict("already mapping: stop or cancel it first")
            if self._mode is not Mode.FREE:
                raise Conflict(f"mapping starts from free (mode {self._mode.value}): "
                               "stop navigation first")
            self._halt_motion()
            self._mapping = MappingSession(self._floor_now(), self._status_pose())
            self._set_mode(Mode.MAPPING)
            log.info("mapping started on floor %s", self._mapping.floor)

        self._call(run)

    def explore(self) -> None:
        """Let the robot map on its own: it drives to the nearest frontier of the live map,
        again and again, then back to where exploring began (``exploration_finished``).
        Teleop or a local move takes over while it runs.

        Raises:
            Conflict: not mapping; already exploring.
        """

        def run() -> None:
            session = self._require_mapping()
            if self._exploration is not None and not self._exploration.done:
                raise Conflict("already exploring")
            self._exploration = Exploration(session.pose)
            log.info("exploration started at %s", session.pose)

        self._call(run)

    def mapping_map(self) -> Map:
        """The map built so far.

        Raises:
            Conflict: not mapping.
        """
        return self._call(lambda: self._require_mapping().live_map())

    def mapping_trajectory(self) -> list[Pose2D]:
        """The robot's path while mapping (the scan poses, optimised).

        Raises:
            Conflict: not mapping.
        """
        return self._call(lambda: self._require_mapping().trajectory())

    def save_mapping(self, name: str, *, overwrite: bool = False) -> object:
        """Save the map built so far under ``name`` (ROS map files in the site store); mapping
        goes on. Returns the saved map's record.

        Raises:
            Conflict: not mapping; ``name`` exists and ``overwrite`` is not set.
            InvalidRequest: a bad name.
        """
        return self._call(lambda: self._save(self._require_mapping().live_map(), name,
                                             overwrite))

    def stop_mapping(self, name: str, *, overwrite: bool = False) -> object:
        """Finish the map (a last optimisation of the whole graph), save it under ``name``, and
        become FREE. Nothing changes when saving fails.

        Raises:
            Conflict: not mapping; ``name`` exists and ``overwrite`` is not set.
            InvalidRequest: a bad name.
        """

        def run() -> object:
            session = self._require_mapping()
            self._check_name_free(name, overwrite)
            record = self._save(session.finish(), name, overwrite)
            self._end_mapping()
            return record

        return self._call(run)

    def cancel_mapping(self) -> None:
        """Drop the map being built and become FREE.

        Raises:
            Conflict: not mapping.
        """

        def run() -> None:
            self._require_mapping()
            self._end_mapping()

        self._call(run)

    def _require_mapping(self) -> MappingSession:
        if self._mode is not Mode.MAPPING or self._mapping is None:
            raise Conflict(f"not mapping (mode {self._mode.value}): start mapping first")
        return self._mapping

    def _check_name_free(self, name: str, overwrite: bool) -> None:
        if overwrite:
            return
        try:
            self.store.map_record(name)
        except NotFound:
            return
        raise Conflict(f"a map called {name!r} exists: give another name, or overwrite it")

    def _save(self, grid: Map, name: str, overwrite: bool) -> object:
        self._check_name_free(name, overwrite)
        floor = self._mapping.floor if self._mapping is not None else None
        try:
            self.store.floor(floor) if floor is not None else None
        except NotFound:
            floor = None
        record = self.store.save_map(name, grid, floor=floor)
        log.info("map %r saved (%d x %d cells)", name, grid.info.width, grid.info.height)
        return record

    def _end_mapping(self) -> None:
        self._halt_motion()
        self._mapping = None
        self._exploration = None
        self._set_mode(Mode.FREE)
