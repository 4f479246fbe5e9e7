"""The robot's power and software life cycle: shut down, reboot, restart the service.

A shutdown announces itself (``PowerOffNotice``), cuts power ``NOTICE_LEAD`` seconds later on
the runtime's clock (navigation stops, the base brakes, every command is refused while off),
and with a reboot powers on again ``REBOOT_GAP`` seconds (plus the asked delay) after that. A
restart of the service announces itself (``SoftwareShutdownNotice``) and reloads navigation at
once. Either way the software e-stop comes back off (it does not survive a restart), and the
robot comes back in the mode it had, on the same map: the map is part of the site, not of the
power state. The robot's own pose is kept (the simulated robot did not move while off).
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING

from polynav.errors import Conflict
from polynav.runtime import events

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

NOTICE_LEAD = 10.0  # [s] from the power-off notice to the power cut
REBOOT_GAP = 5.0  # [s] off before a reboot powers on


class PowerCycle:
    """Shutdowns, reboots and service restarts of one runtime."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime
        self._pending = False
        self._map: str | None = None

    @property
    def shutting_down(self) -> bool:
        """A shutdown was announced and the robot is not back on yet."""
        return self._pending

    def shutdown(self, *, reboot: bool, delay: float = 0.0) -> None:
        """Announce a power-off in ``NOTICE_LEAD`` seconds; with ``reboot``, power on again
        ``REBOOT_GAP + delay`` seconds after it.

        Raises:
            Conflict: a shutdown is already under way (or the robot is off).
        """
        runtime = self._runtime

        def announce() -> None:
            if self._pending:
                raise Conflict("a shutdown is already under way")
            self._pending = True
            runtime.publish(events.PowerOffNotice(runtime.now(), reboot, NOTICE_LEAD, delay))
            runtime.schedule(NOTICE_LEAD, lambda: self._power_off(reboot, delay))
            log.warning("power off in %gs%s", NOTICE_LEAD,
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

    def _power_off(self, reboot: bool, delay: float) -> None:
        runtime = self._runtime
        self._map = runtime.map_name
        runtime.stop_navigation()
        runtime.powered = False
        log.warning("powered off")
        if reboot:
            runtime.schedule(REBOOT_GAP + delay, self._power_on)

    def _power_on(self) -> None:
        runtime = self._runtime
        runtime.powered = True
        self._pending = False
        runtime.set_software_estop(False)
        if self._map is not None:
            runtime.start_navigation(self._map)
        log.warning("powered on")
