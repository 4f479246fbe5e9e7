"""The robot's power and software life cycle: shut down, reboot, restart the service.

A shutdown announces itself (``PowerOffNotice``), cuts power ``NOTICE_LEAD`` seconds later on
the runtime's clock (navigation stops, the base brakes, every command is refused while off),
and with a reboot powers on again ``REBOOT_GAP`` seconds (plus the asked delay) after that. A
restart of the service announces itself (``SoftwareShutdownNotice``) and reloads navigation at
once. Either way the software e-stop comes back off (it does not survive a restart), and the
robot comes back in the mode it had, on the same map: the map is part of the site, not of the
power state. The robot's own pose is kept (the simulated robot did not move while off).

The power cut is a timer: it must never fail half-done (issue 32, docs/decisions.md "Timers
never fail half-done"). So a shutdown asked while the robot maps or rides a lift is refused at
once (stop or cancel the map; wait until it has left the car), and starting to map while one is
announced is refused (:meth:`PowerCycle.refuse_if_pending`). At the cut the running task is
cancelled, a goal (a docking included) is cancelled, and a robot that entered a lift during
the notice is waited for until it is out of the car (checked every :data:`LIFT_RECHECK`
seconds, at most :data:`LIFT_WAIT`); only then is the power cut. Nothing the cut does raises.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING

from polynav.errors import Conflict, PolynavError
from polynav.runtime import events
from polynav.runtime.busy import in_lift_car
from polynav.runtime.config import Mode

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

NOTICE_LEAD = 10.0  # [s] from the power-off notice to the power cut
REBOOT_GAP = 5.0  # [s] off before a reboot powers on
LIFT_RECHECK = 1.0  # [s] a cut waiting for the robot to leave a lift car checks this often
LIFT_WAIT = 600.0  # [s] then cuts anyway (the ride's own timeouts end it long before)


class PowerCycle:
    """Shutdowns, reboots and service restarts of one runtime."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime
        self._pending = False
        self._map: str | None = None
        #: [s] from the notice to the cut (tests shorten it to land the cut in a phase).
        self.notice_lead = NOTICE_LEAD

    @property
    def shutting_down(self) -> bool:
        """A shutdown was announced and the robot is not back on yet."""
        return self._pending

    def shutdown(self, *, reboot: bool, delay: float = 0.0) -> None:
        """Announce a power-off in ``NOTICE_LEAD`` seconds; with ``reboot``, power on again
        ``REBOOT_GAP + delay`` seconds after it.

        Raises:
            Conflict: a shutdown is already under way (or the robot is off); the robot is
                mapping (stop or cancel the map first) or in a lift car (wait until it is
                out). Nothing is announced then.
        """
        runtime = self._runtime

        def announce() -> None:
            if self._pending:
                raise Conflict("a shutdown is already under way")
            if runtime.mode is Mode.MAPPING:
                raise Conflict("mapping is running: stop (save) or cancel mapping before "
                               "powering off")
            car = in_lift_car(runtime)
            if car is not None:
                raise Conflict(f"the robot is riding lift {car}: power off once it has left "
                               "the lift, or cancel its goal first")
            self._pending = True
            lead = self.notice_lead
            runtime.publish(events.PowerOffNotice(runtime.now(), reboot, lead, delay))
            runtime.schedule(lead, lambda: self._power_off(reboot, delay, lead))
            log.warning("power off in %gs%s", lead,
                        f", back on {REBOOT_GAP + delay:g}s later" if reboot else "")

        runtime.run_between_ticks(announce)

    def restart_software(self) -> None:
        """Restart the navigation service: notice, then navigation reloaded on its map.

        Raises:
            Conflict: a shutdown is under way.
        """
        runtime = self._runtime

        def restart() -> None:
            if self._pending:
                raise Conflict("a shutdown is under way")
            runtime.publish(events.SoftwareShutdownNotice(runtime.now()))
            map_name = runtime.map_name
            runtime.stop_navigation()
            runtime.set_software_estop(False)
            if map_name is not None:
                runtime.start_navigation(map_name)
            log.info("software restarted")

        runtime.run_between_ticks(restart)

    def refuse_if_pending(self, what: str) -> None:
        """Refuse to begin ``what`` (mapping) while a shutdown is announced: the cut would have
        to end it. Raises Conflict."""
        if self._pending:
            raise Conflict(f"a shutdown is under way: {what} is refused until the robot is "
                           "back on")

    def _power_off(self, reboot: bool, delay: float, waited: float) -> None:
        """The cut (a timer, on the loop): end what runs, then power off. Never raises."""
        runtime = self._runtime
        car = in_lift_car(runtime)
        if car is not None and waited < self.notice_lead + LIFT_WAIT:
            log.warning("power off waits: the robot is riding lift %s", car)
            runtime.schedule(LIFT_RECHECK, lambda: self._power_off(
                reboot, delay, waited + LIFT_RECHECK))
            return
        self._map = runtime.map_name
        runtime._end_activities("cancelled: the robot powered off")
        runtime.powered = False
        log.warning("powered off")
        if reboot:
            runtime.schedule(REBOOT_GAP + delay, self._power_on)

    def _power_on(self) -> None:
        """Power on (a timer): back on the map it had; a map that will not load (deleted while
        off) leaves the robot FREE, logged, never a failed timer."""
        runtime = self._runtime
        runtime.powered = True
        self._pending = False
        runtime.set_software_estop(False)
        if self._map is not None:
            try:
                runtime.start_navigation(self._map)
            except PolynavError as exc:
                log.error("powered on FREE: navigation on %r did not start: %s", self._map, exc)
        log.warning("powered on")
