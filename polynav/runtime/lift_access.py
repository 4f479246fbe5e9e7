"""The building's lift cars as a runtime part: reading them, an operator's request, a car
held for a task, lift sessions, and the path costs the router weighs routes with.

A part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` by subject, the base of
:class:`~polynav.runtime.lift_commands.LiftCommands` (the lift sequence).

A task may drive a car step by step (galileo-tasks-bt-ws §5.3 #13, #18, #19: call it, enter,
ride, leave) instead of one goal across floors. :meth:`LiftAccess.hold_lift` asks for the car
as the lift sequence does: the car's session first (the lease on ``lift:<car>``, so robots of
a building still take a car one at a time), then the car to the floor with its doors open; the
session is renewed every control tick while held (:meth:`LiftAccess._hold_tick`) and given
back by :meth:`LiftAccess.release_lift`. A car whose session another robot or an operator holds
refuses the call (:class:`~polynav.robot.lift.LiftBusy`): the car is occupied.
"""

from __future__ import annotations

import abc
import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass

from polynav.errors import Conflict, InvalidRequest, NotFound, look_up
from polynav.nav.stack import StackConfig
from polynav.robot.lift import (
    DoorRequest,
    Lift,
    LiftBusy,
    LiftError,
    LiftMode,
    LiftOutOfService,
    LiftRequest,
)
from polynav.robot.sim.lift_car import SimLiftCar
from polynav.routing import connections as site_connections
from polynav.routing.path_costs import PlannedPathCosts
from polynav.routing.router import Router
from polynav.runtime.internals import RuntimeParts
from polynav.runtime.lift_sessions import LiftSessions, LocalLiftSessions

log = logging.getLogger(__name__)


@dataclass(slots=True)
class LiftHold:
    """A car held for a task: asked to ``floor`` with its doors open once ``placed`` (the
    session granted and the car asked); ``refused`` says why the car turned the call down."""

    car: str
    floor: str
    placed: bool = False
    refused: str = ""


class LiftAccess(RuntimeParts):
    """The cars, their sessions and the router's costs (see the module docstring)."""

    _router: Router | None
    _path_costs: PlannedPathCosts | None
    _lift_sessions: LiftSessions | None
    _lift_hold: LiftHold | None

    # -- reads ---------------------------------------------------------------------------------

    @property
    def robot_id(self) -> str:
        """This robot's id: the name lift sessions and the fleet know it by."""
        return self._place.name

    @property
    def lifts(self) -> Mapping[str, Lift]:
        """The building's lift cars by name (the simulator's; a real site's lift controllers)."""
        return self._place.lifts

    def lift(self, car: str) -> Lift:
        """Car ``car``.

        Raises:
            NotFound: no such car.
        """
        return look_up(self.lifts, "lift", car)

    def use_lift_sessions(self, sessions: LiftSessions) -> None:
        """Take lift sessions from ``sessions`` (the fleet's lease book) from now on."""
        self._lift_sessions = sessions

    # -- commands ------------------------------------------------------------------------------

    def request_lift(self, car: str, request: LiftRequest) -> None:
        """Pass ``request`` to car ``car`` between ticks (an operator's call, or ending their
        session).

        Raises:
            NotFound: no such car. InvalidRequest: a floor it does not serve.
            LiftError: out of service, or another session holds it.
        """
        lift = self.lift(car)
        self._call(lambda: lift.request(request))

    def set_lift_mode(self, car: str, mode: LiftMode) -> None:
        """Put a simulated car in or out of service (a real car's mode is its controller's).

        Raises:
            NotFound: no such car.
            Conflict: a real car (its controller sets its mode).
        """
        found = self.lift(car)
        if not isinstance(found, SimLiftCar):
            raise Conflict(f"lift {car} is a real car: its controller sets its mode")
        self._call(lambda: found.set_mode(mode))

    # -- a car held for a task (between ticks) ------------------------------------------------

    def hold_lift(self, car: str | None, level: int | None) -> LiftHold:
        """Ask a car to the floor of ``level`` (``None``: the robot's floor) with its doors
        open, on this robot's session, and hold it until :meth:`release_lift`.

        The car is ``car``, else the one held already, else the nearest car stopping on the
        robot's map (by its outside point) that serves that floor. Call between ticks.

        Raises:
            NotFound: no such car. InvalidRequest: no floor at ``level``, no car stops here,
                or the car does not serve that floor. LiftBusy: another session holds the
                car (it is occupied). LiftOutOfService: the car is out of service.
        """
        floor = self._floor_at(level)
        held = self._lift_hold
        name = car or (held.car if held is not None else None) or self._nearest_car(floor)
        lift = self.lift(name)
        state = lift.state()
        if floor not in state.floors:
            raise InvalidRequest("level", f"lift {name} does not serve {floor}")
        if state.mode is LiftMode.OUT_OF_SERVICE:
            raise LiftOutOfService(f"lift {name} is out of service")
        if state.session_id not in ("", self.robot_id):
            raise LiftBusy(f"lift {name} is occupied: {state.session_id} holds it")
        if held is not None and held.car != name:
            self.release_lift()
        hold = LiftHold(name, floor)
        self._lift_hold = hold
        log.info("lift %s held for a task: to %s", name, floor)
        self._hold_tick(self.now())
        return hold

    def held_lift(self) -> LiftHold | None:
        """The car held for a task, if any."""
        return self._lift_hold

    def release_lift(self) -> None:
        """End the held car's session and give its lease back (nothing when none is held).
        Call between ticks."""
        hold = self._lift_hold
        if hold is None:
            return
        self._lift_hold = None
        car = self.lifts.get(hold.car)
        if car is not None and car.state().session_id == self.robot_id:
            try:
                car.request(LiftRequest(self.robot_id, end_session=True))
            except LiftError:
                log.debug("lift %s: session already over", hold.car)
        self._sessions().release(hold.car, self.now())
        log.info("lift %s given back", hold.car)

    def _hold_tick(self, now: float) -> None:
        """Renew the held car's session; place the call once the session is granted."""
        hold = self._lift_hold
        if hold is None or hold.refused:
            return
        sessions = self._sessions()
        sessions.request(hold.car, now)
        if hold.placed or not sessions.granted(hold.car, now):
            return
        try:
            self.lift(hold.car).request(LiftRequest(self.robot_id, hold.floor, DoorRequest.OPEN))
        except (LiftError, NotFound, InvalidRequest) as exc:
            hold.refused = str(exc)
            log.info("lift %s refused the call: %s", hold.car, exc)
            return
        hold.placed = True

    def _floor_at(self, level: int | None) -> str:
        if level is None:
            floor = self._floor_now()
            if floor is None:
                raise InvalidRequest("level", "the robot's floor is not known")
            return floor
        for record in self.store.floors():
            if getattr(record, "level", None) == level:
                return str(getattr(record, "name", ""))
        raise InvalidRequest("level", f"no floor of the site is at level {level}")

    def _nearest_car(self, floor: str) -> str:
        map_name = self._map_name
        if map_name is None:
            raise InvalidRequest("lift", "the robot is not navigating: name the lift")
        here = self._status_pose()
        best: tuple[float, str] | None = None
        for connection in site_connections.parse(self.store.connections()).lifts:
            stop = connection.stop_on(map_name)
            if stop is None or floor not in (s.floor for s in connection.stops):
                continue
            door = self.store.point(map_name, stop.outside).pose
            distance = math.hypot(door.x - here.x, door.y - here.y)
            if best is None or distance < best[0]:
                best = (distance, connection.car)
        if best is None:
            raise InvalidRequest("lift", f"no lift stops on {map_name} and serves {floor}")
        return best[1]

    # -- shared with the sequence --------------------------------------------------------------

    def _costs(self) -> PlannedPathCosts:
        costs = self._path_costs
        if costs is None:
            config = self.stack_config()
            costs = PlannedPathCosts(self.store, config.costmap, config.planner)
            self._path_costs = costs
        return costs

    def _sessions(self) -> LiftSessions:
        if self._lift_sessions is None:
            self._lift_sessions = LocalLiftSessions(self.robot_id)
        return self._lift_sessions

    @abc.abstractmethod
    def stack_config(self) -> StackConfig:
        """The stack's configuration now (the runtime's)."""
