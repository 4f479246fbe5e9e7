"""The building's lift cars as a runtime part: reading them, an operator's request, lift
sessions, and the path costs the router weighs routes with.

A part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` by subject, the base of
:class:`~polynav.runtime.lift_commands.LiftCommands` (the lift sequence).
"""

from __future__ import annotations

import abc
import logging
from collections.abc import Mapping

from polynav.errors import NotFound
from polynav.nav.stack import StackConfig
from polynav.robot.lift import Lift, LiftMode, LiftRequest
from polynav.robot.sim.simulation import Simulation
from polynav.routing.path_costs import PlannedPathCosts
from polynav.routing.router import Router
from polynav.runtime.internals import RuntimeParts
from polynav.runtime.lift_sessions import LiftSessions, LocalLiftSessions

log = logging.getLogger(__name__)


class LiftAccess(RuntimeParts):
    """The cars, their sessions and the router's costs (see the module docstring)."""

    _sim: Simulation
    _router: Router | None
    _path_costs: PlannedPathCosts | None
    _lift_sessions: LiftSessions | None

    # -- reads ---------------------------------------------------------------------------------

    @property
    def robot_id(self) -> str:
        """This robot's id: the name lift sessions and the fleet know it by."""
        return self._sim.name

    @property
    def lifts(self) -> Mapping[str, Lift]:
        """The building's lift cars by name (the simulator's; a real site's lift controllers)."""
        return self._sim.scene.lifts

    def lift(self, car: str) -> Lift:
        """Car ``car``.

        Raises:
            NotFound: no such car.
        """
        found = self.lifts.get(car)
        if found is None:
            raise NotFound("lift", car)
        return found

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
        """
        found = self._sim.scene.lifts.get(car)
        if found is None:
            raise NotFound("lift", car)
        self._call(lambda: found.set_mode(mode))

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
