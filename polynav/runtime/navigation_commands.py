"""Navigation commands of the runtime: start and stop navigation on a map, the initial pose,
relocalization, the navigation stack's life (built for a map, rebuilt for new settings,
dropped at the end), and its navigator's events published as the runtime's.

Part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` (see
:mod:`~polynav.runtime.internals`). Starting or stopping navigation from outside a task takes
the robot: the running task gives way (:meth:`~polynav.tasks.engine.TaskEngine.give_way`).
"""

from __future__ import annotations

import logging
from dataclasses import replace
from typing import TYPE_CHECKING

from polynav.errors import Conflict, InvalidRequest, PolynavError
from polynav.geometry import Pose2D, Twist
from polynav.mapping.relocalization import Relocalization
from polynav.maps.keepout import Keepout
from polynav.maps.map import Map
from polynav.nav import events as nav_events
from polynav.nav.stack import NavigationStack
from polynav.runtime import events
from polynav.runtime.config import Mode
from polynav.runtime.internals import RuntimeParts
from polynav.runtime.navigation_events import translate
from polynav.runtime.placement import initial_point

if TYPE_CHECKING:
    from polynav.runtime.route_run import RouteRun

log = logging.getLogger(__name__)


class NavigationCommands(RuntimeParts):
    _route: RouteRun | None  # a goal on another map (lift commands)

    def start_navigation(
        self, map_name: str, *, point: str | None = None, pose: Pose2D | None = None
    ) -> None:
        """Load ``map_name`` and its keepouts, localize, and become NAVIGATING (via BUSY).

        The initial pose is the named ``point`` of that map, else ``pose``, else (simulator
        only) the robot's true pose when it is already on the map's floor, else the map's
        initial point. Starting again while NAVIGATING cancels any goal and reloads.

        Raises:
            NotFound: unknown map or point.
            InvalidRequest: both ``point`` and ``pose``; a map on no simulated floor; no initial
                pose to be had; a pose inside a wall.
            Conflict: MAPPING.
        """
        start = self._map_start(map_name, point, pose)
        keepouts = tuple(self.store.keepouts(start.name))
        fallback = initial_point(self.store, start.name)
        self._call(lambda: self._start_navigation(
            start.name, start.floor, start.grid, keepouts, start.initial, fallback))

    def stop_navigation(self) -> None:
        """Cancel any goal, unload the map and become FREE (via BUSY); nothing when FREE.

        Raises:
            Conflict: MAPPING.
        """
        self._call(self._stop_navigation)

    def reload_keepouts(self) -> None:
        """Apply the site's keepouts of the map navigated on now (after an edit), so the next
        plan and the running one respect them without a restart of navigation."""

        def run() -> None:
            if self._map_name is None or self._mapless:
                return
            self._keepouts = tuple(self.store.keepouts(self._map_name))
            if self._stack is not None:
                self._stack.costmap.set_keepouts(self._keepouts)

        self._call(run)

    def set_initial_pose(self, pose: Pose2D) -> None:
        """Restart localization near ``pose`` on the current map.

        Raises:
            Conflict: not NAVIGATING, or a goal is active (cancel it first).
            InvalidRequest: the pose lies in a wall (simulator placement).
        """

        def run() -> None:
            stack = self._require_navigating()
            if self._mapless:
                raise Conflict("navigating without a map: the frame is odometry's, there is no "
                               "map pose to set (start navigation on a map first)")
            if self._goal_active():
                raise Conflict("a goal is active: cancel it before setting the initial pose")
            assert self._map_name is not None
            self._place.place(self._place.floor, pose)
            now = self.now()
            stack.initialize(pose, now)
            self._publish(events.PoseInitialized(now, pose))
            self._check_localization(now)

        self._call(run)

    def relocalize(self) -> Relocalization:
        """Find the robot on the current map from its scan alone, with no prior, and restart
        localization there (it also runs by itself while localization is LOST).

        Raises:
            Conflict: not NAVIGATING.
            NotLocalized: the scan matches nowhere well enough, or several places alike.
        """

        def run() -> Relocalization:
            self._require_navigating()
            assert self._grid is not None
            return self._recovery.relocalize(self._grid, self._robot.read_scan())

        return self._call(run)

    # -- navigation internals ----------------------------------------------------------------

    def _start_navigation(
        self,
        name: str,
        floor: str,
        grid: Map,
        keepouts: tuple[Keepout, ...],
        initial: Pose2D | None,
        fallback: Pose2D | None,
    ) -> None:
        if self._mode is Mode.MAPPING:
            raise Conflict("mapping is running: stop it before navigating")
        if self._mode is Mode.BUSY:
            raise Conflict("the robot is busy")
        if initial is None:
            truth = self._place.true_pose() if self._place.floor == floor else None
            if truth is not None:
                initial = truth
            elif fallback is not None:
                initial = fallback
            else:
                raise InvalidRequest(
                    "point", f"map {name!r} has no initial point: give the initial point or pose"
                )
        self._place.place(floor, initial)  # may raise before anything changed
        self.tasks.engine.give_way("cancelled: navigation was started")
        self._cancel_goal()
        self._halt_motion()
        self._set_mode(Mode.BUSY)
        self._attempts.new_session()
        now = self.now()
        self._mapless = False
        self._map_name = name
        self._grid = grid
        self._keepouts = keepouts
        stack = self._new_stack()
        stack.initialize(initial, now)
        self._stack = stack
        self._settings_dirty = False
        log.info("navigation started on map %r at %s", name, initial)
        self._publish(events.PoseInitialized(now, initial))
        self._set_mode(Mode.NAVIGATING)

    def _end_activities(self, note: str) -> None:
        """End whatever the robot does (a power cut): the running task (with ``note``), a map
        being built (dropped: a cut cannot save), a goal or patrol (a docking included),
        teleop and local moves; then unload navigation. Between ticks; never raises, as its
        callers are timers."""
        try:
            self.tasks.engine.give_way(note)
        except PolynavError:
            log.error("the running task did not end", exc_info=True)
        if self._mode is Mode.MAPPING:
            log.error("mapping was running at the power cut: the map being built is dropped")
            self._end_mapping()
        self._cancel_goal()
        self._halt_motion()
        if self._mapping_jobs.finishing is not None:
            log.warning("a map is being finished and saved: the robot is free once it is saved")
            return
        self._stop_navigation()

    def _stop_navigation(self) -> None:
        if self._mode is Mode.MAPPING:
            raise Conflict("mapping is running: stop mapping instead")
        if self._mapping_jobs.finishing is not None:
            raise Conflict("mapping is stopping: the robot is free once the map is saved")
        if self._mode is Mode.FREE:
            return
        self._set_mode(Mode.BUSY)
        self.tasks.engine.give_way("cancelled: navigation was stopped")
        self._cancel_goal()
        self._halt_motion()
        self._stack = None
        self._mapless = False
        self._map_name = None
        self._grid = None
        self._keepouts = ()
        self._robot.drive(Twist())
        log.info("navigation stopped")
        self._set_mode(Mode.FREE)
        self._check_localization(self.now())

    def _new_stack(self) -> NavigationStack:
        config = self.carts.stack_config(self._settings.stack_config(self._base_stack_config))
        if config.control_rate != self.config.control_rate:
            config = replace(config, control_rate=self.config.control_rate)
        if self._mapless:
            stack = self._new_mapless_stack(config)
        else:
            assert self._grid is not None
            stack = NavigationStack(self._robot, self._grid, config=config,
                                    on_event=self._on_nav_event)
        if self._keepouts:
            stack.costmap.set_keepouts(self._keepouts)
        stack.software_estop = self._software_estop
        self._attempts.new_stack()
        return stack

    def _rebuild_stack(self) -> NavigationStack:
        """A stack with the current settings; localization carries over (it keeps tracking)."""
        old = self._stack
        assert old is not None
        stack = self._new_stack()
        stack.localizer = old.localizer
        self._stack = stack
        self._settings_dirty = False
        log.info("navigation stack rebuilt with new settings")
        return stack

    def _restart_localization(self, pose: Pose2D) -> None:
        """Restart tracking at ``pose`` (a relocalization's answer; the robot is not moved)."""
        assert self._stack is not None
        now = self.now()
        self._stack.initialize(pose, now)
        self._publish(events.PoseInitialized(now, pose))
        self._check_localization(now)

    # -- navigator events ----------------------------------------------------------------------

    def _on_nav_event(self, event: nav_events.NavigationEvent) -> None:
        run = self._route
        if run is not None:  # a leg of a goal on another map: reported as the route's
            for runtime_event in translate(event, run.attempt_id, None):
                if not isinstance(runtime_event, _LEG_ENDS):
                    self._publish(runtime_event)
            return
        for runtime_event in self._attempts.record(event):
            self._publish(runtime_event)


_LEG_ENDS = (events.NavigationStarted, events.NavigationSucceeded, events.NavigationFailed,
             events.NavigationCanceled)
"""A route's legs start and end inside its one attempt: those events are the route's own."""
