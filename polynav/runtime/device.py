"""The robot as a device: what a robot's owner manages besides navigation (network, lights,
self-diagnosis, power and software life cycle), and the device-level alarms.

:class:`Device` is a runtime service: the runtime builds it and ticks it every control period
with the velocity it commanded. It runs the self-diagnosis, and watches for the robot being
moved by hand (``RobotDisplaced``) and for something inside its housing
(``ForeignObjectDetected``). The light strip is two persisted settings (brightness and colour),
so it keeps its state across restarts as the vendors' strips keep theirs in flash.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from polynav.errors import Conflict, InvalidRequest
from polynav.geometry import Twist
from polynav.robot.interface import BatteryState
from polynav.robot.sim.wifi import VisibleNetwork
from polynav.runtime.power import PowerCycle
from polynav.runtime.self_check import SelfCheck
from polynav.runtime.watchers import DisplacementWatcher, ForeignObjectWatcher

if TYPE_CHECKING:
    from polynav.robot.sim.simulation import Simulation
    from polynav.runtime.robot_runtime import RobotRuntime

FOREIGN_OBJECT_SECTOR = math.radians(10.0)


@dataclass(frozen=True, slots=True)
class LightStrip:
    """Brightness and colour [0..100 each]."""

    luminance: float
    red: float
    green: float
    blue: float


@dataclass(frozen=True, slots=True)
class NetworkState:
    """What the wireless card sees and is joined to."""

    visible: list[VisibleNetwork]
    active: str | None
    ip_address: str
    mac: str


class Device:
    """The device services of one robot (``runtime.device``)."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._runtime = runtime
        self.power = PowerCycle(runtime)
        self.self_check = SelfCheck(runtime.robot, radio_ok=True)
        self._displacement = DisplacementWatcher()
        self._foreign_object = ForeignObjectWatcher(FOREIGN_OBJECT_SECTOR)

    def tick(self, now: float, commanded: Twist) -> None:
        """One control period (called by the runtime's loop, between commands)."""
        robot = self._runtime.robot
        self.self_check.tick(now)
        for event in (
            self._displacement.update(now, robot.read_odometry(), commanded),
            self._foreign_object.update(now, robot.read_scan()),
        ):
            if event is not None:
                self._runtime.publish(event)

    # -- light strip ---------------------------------------------------------------------------

    @property
    def light(self) -> LightStrip:
        s = self._runtime.settings()
        return LightStrip(s.led_luminance, s.led_red, s.led_green, s.led_blue)

    def set_light(
        self,
        *,
        luminance: float | None = None,
        colour: tuple[float, float, float] | None = None,
    ) -> LightStrip:
        """Change and persist the strip's brightness and/or colour.

        Raises:
            InvalidRequest: a value outside 0..100, or a colour of all zeros.
        """
        changes: dict[str, object] = {}
        if luminance is not None:
            changes["led_luminance"] = luminance
        if colour is not None:
            changes.update(zip(("led_red", "led_green", "led_blue"), colour, strict=True))
        if not changes:
            raise InvalidRequest("light", "nothing to change")
        self._runtime.update_settings(changes)
        return self.light

    # -- network -------------------------------------------------------------------------------

    def network(self) -> NetworkState:
        """The wireless card's view where the robot stands now."""
        sim = self._wireless()
        visible = self._runtime.run_between_ticks(sim.wifi_scan)
        card = sim.wifi
        return NetworkState(visible, card.active(visible), card.ip_address(visible), card.mac)

    def join_network(self, ssid: str, password: str | None) -> None:
        """Join ``ssid`` (a network joined before needs no password).

        Raises:
            InvalidRequest: not in range, a missing or wrong password.
        """
        sim = self._wireless()
        visible = self._runtime.run_between_ticks(sim.wifi_scan)
        sim.wifi.connect(ssid, password, visible)

    def _wireless(self) -> Simulation:
        """The simulator, whose wireless card the robot's network commands use.

        Raises:
            Conflict: a real robot: its host's network is not reachable through its driver.
        """
        if not self._runtime.is_simulated:
            raise Conflict("this robot's wireless card is its host's: polynav does not manage "
                           "the network of a robot it drives over rosbridge")
        return self._runtime.simulation

    # -- power ---------------------------------------------------------------------------------

    def battery(self) -> BatteryState:
        return self._runtime.robot.read_battery()
