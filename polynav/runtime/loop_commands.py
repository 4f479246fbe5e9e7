"""The runtime's loop as its callers see it: run it (a thread at a speed, or simulated time
as fast as the machine goes), run commands and functions between ticks, timers and step
listeners.

Part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` (see
:mod:`~polynav.runtime.internals`). The pacing, the thread and the command queue are
:class:`~polynav.runtime.loop.CommandLoop`'s; timers and listeners are
:class:`~polynav.runtime.step_hooks.StepHooks`'; this part only wires them to the runtime (the
power state that refuses commands, the automations closed on stop, one physics step's order).
"""

from __future__ import annotations

import abc
import logging
from collections.abc import Callable
from typing import TYPE_CHECKING, TypeVar

from polynav.errors import Conflict
from polynav.robot.interface import Backend
from polynav.runtime.internals import RuntimeParts
from polynav.runtime.loop import CommandLoop
from polynav.runtime.step_hooks import StepHooks

if TYPE_CHECKING:
    from polynav.runtime.automation_tasks import AutomationTasks

log = logging.getLogger(__name__)

T = TypeVar("T")


class LoopCommands(RuntimeParts):
    """Running the loop and calling into it (set up by the runtime)."""

    _loop: CommandLoop
    _hooks: StepHooks
    _backend: Backend
    automations: AutomationTasks
    powered: bool

    @abc.abstractmethod
    def tick(self) -> None:
        """Everything of one physics step but the physics (the control tick part)."""

    def run_between_ticks(self, fn: Callable[[], T]) -> T:
        """Run ``fn`` between ticks (on the loop thread when it runs) and return its result:
        for services and queries that read or change several parts consistently."""
        return self._call(fn)

    def schedule(self, delay: float, fn: Callable[[], None]) -> None:
        """Run ``fn`` on the loop, between steps, ``delay`` seconds of the runtime's clock from
        now (for services: a power-off 10 s after its notice). Call it between ticks."""
        self._hooks.schedule(self.now() + max(0.0, delay), fn)

    # -- running -------------------------------------------------------------------------------

    def advance(self, seconds: float) -> None:
        """Run the loop for ``seconds`` of simulated time, as fast as the machine goes.

        Raises:
            Conflict: the loop thread is running (:meth:`start`).
        """
        self.advance_until(lambda: False, timeout=seconds)

    def advance_until(self, done: Callable[[], bool], timeout: float) -> bool:
        """Run the loop until ``done()`` holds (checked every physics step) or ``timeout``
        simulated seconds pass.

        Returns:
            Whether ``done()`` held.

        Raises:
            Conflict: the loop thread is running.
        """
        return self._loop.advance_until(done, timeout)

    def start(self) -> None:
        """Run the loop on a daemon thread, simulated time paced at ``speed`` × wall time."""
        self._loop.start()
        log.info("runtime started at %gx real time", self.config.speed)

    def stop(self) -> None:
        """Stop the loop thread and wait for it; queued commands still run. Idempotent."""
        self.automations.close()
        if self._loop.stop():
            log.info("runtime stopped at t=%.2f", self.now())

    @property
    def running(self) -> bool:
        return self._loop.running

    def _call(self, fn: Callable[[], T]) -> T:
        """Run a command between ticks: on the loop thread when it runs, else here.

        Raises:
            Conflict: the robot is powered off.
        """
        if not self.powered:
            raise Conflict("the robot is powered off")
        return self._loop.call(fn)

    # -- the loop ------------------------------------------------------------------------------

    def add_step_listener(self, listener: Callable[[float], None]) -> Callable[[], None]:
        """Call ``listener(now)`` on the loop after every physics step, when the backend's
        readings are new: for servers that stream sensors at their own rates on the runtime's
        clock (a scan at 15 Hz of simulated time). It must be quick and must not block: copy what
        it needs and hand it to its own thread. Returns the function that removes it."""
        return self._hooks.add_listener(listener)

    def stepped(self) -> None:
        """Tell the step listeners a physics step happened (the fleet's shared world calls it
        for each robot after stepping the world once)."""
        self._hooks.stepped(self.now())

    def _step(self) -> None:
        self.tick()
        self._backend.step()
        self.stepped()
