"""A polynav robot as a VDA 5050 vehicle on an MQTT broker (§6.14-6.17).

:class:`VehicleLink` is one robot's MQTT client: it connects under
``uagv/v2/<manufacturer>/<serialNumber>/`` with its last will (``connection``
CONNECTIONBROKEN, retained, QoS 1), says ONLINE once connected, publishes its factsheet
(retained), and says OFFLINE before it closes. Its :attr:`VehicleLink.transport` is what the
robot's :class:`~polynav.fleet.agent.RobotAgent` (orders, instant actions, state,
visualization) and, in a building, the fleet's master control use: the transport is the only
thing that changes between one process and a broker.

:class:`LoneVehicle` is a lone robot (``polynav run --broker``) on a broker under some master
control: its agent is ticked on the robot's loop, every control period, and asks for no
zones or lift sessions (no polynav fleet lends them).
"""

from __future__ import annotations

import argparse
import datetime as dt
import logging
import math
import threading
from collections.abc import Callable
from dataclasses import dataclass

import orjson

from polynav.errors import ConfigError
from polynav.fleet import codec
from polynav.fleet import messages as m
from polynav.fleet.agent import RobotAgent
from polynav.fleet.factsheet import factsheet
from polynav.fleet.mqtt_transport import MqttTransport
from polynav.fleet.vda5050 import validation
from polynav.robot.profile import RobotProfile
from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class VehicleConfig:
    """How a robot speaks VDA 5050 over MQTT.

    Attributes:
        broker: ``mqtt://host[:port]``.
        version: ``"2.0.0"`` or ``"2.1.0"``.
        manufacturer: the third level of the topics.
        state_period: the longest between two states [s]; the standard asks for at most 30.
        visualization_period: between two visualization messages [s]; None for none.
        connect_timeout: how long to try to reach the broker at start-up [s].
    """

    broker: str
    version: str = m.DEFAULT_VERSION
    manufacturer: str = m.DEFAULT_MANUFACTURER
    state_period: float = 30.0
    visualization_period: float | None = 1.0
    connect_timeout: float = 10.0

    def __post_init__(self) -> None:
        if self.version not in validation.VERSIONS:
            raise ConfigError("fleet.vda.version",
                              f"{self.version!r}: one of {', '.join(validation.VERSIONS)}")
        if not self.manufacturer or any(c in self.manufacturer for c in "/+#"):
            raise ConfigError("fleet.vda.manufacturer", "non-empty, without / + or #")
        if not 0 < self.state_period <= 30.0:
            raise ConfigError("fleet.vda.state_period", "must be in (0, 30] s")
        if self.visualization_period is not None and self.visualization_period <= 0:
            raise ConfigError("fleet.vda.visualization_period", "must be > 0")
        if not (math.isfinite(self.connect_timeout) and self.connect_timeout > 0):
            raise ConfigError("fleet.vda.connect_timeout", "must be a number of seconds > 0")


def config_from_args(args: argparse.Namespace) -> VehicleConfig:
    """``polynav run``'s ``--broker`` and ``--vda-*`` options as a vehicle config.

    Raises:
        ConfigError: a bad version, manufacturer or rate.
    """
    rate = float(args.vda_visualization_rate)
    if rate < 0:
        raise ConfigError("fleet.vda.visualization_rate", "must be >= 0")
    return VehicleConfig(str(args.broker), version=str(args.vda_version),
                         manufacturer=str(args.vda_manufacturer),
                         visualization_period=1.0 / rate if rate > 0 else None,
                         connect_timeout=float(args.connect_timeout))


class VehicleLink:
    """One robot's connection to the broker (see the module docstring).

    Args:
        serial_number: the robot's serial number, the fourth level of its topics.
        profile: the robot, for its factsheet.
        config: the broker and protocol settings.
        clock: site time [s], for the headers.
        epoch: the UTC moment site time 0 stands for.
        order_period: how often the robot reads orders [s] (its factsheet says so).

    Raises:
        ConfigError: a bad broker URL. BrokerUnreachable: no broker within the timeout.
    """

    def __init__(self, serial_number: str, profile: RobotProfile, config: VehicleConfig, *,
                 clock: Callable[[], float], epoch: dt.datetime | None = None,
                 order_period: float = 0.1) -> None:
        self.serial_number = serial_number
        self.config = config
        self._profile = profile
        self._order_period = order_period
        self.headers = m.Headers(config.version, config.manufacturer, clock, epoch)
        self._connection_topic = m.topic(serial_number, m.Connection, config.manufacturer)
        will = codec.encode(self._connection(m.ConnectionState.CONNECTIONBROKEN))
        self.transport = MqttTransport(
            config.broker, f"{config.manufacturer}/{serial_number}",
            will=(self._connection_topic, will, 1, True),
            connect_timeout=config.connect_timeout)
        self._closed = False
        # The network thread (after a reconnection) and the robot's loop both publish here.
        self._lock = threading.Lock()
        self._say_online()
        self.transport.add_reconnect_listener(self._reconnected)
        log.info("vehicle %s/%s on %s (VDA 5050 %s)", config.manufacturer, serial_number,
                 config.broker, config.version)

    def publish_factsheet(self) -> None:
        """Publish the factsheet (retained)."""
        with self._lock:
            sheet = factsheet(
                self._profile, serial_number=self.serial_number,
                header=self.headers.stamp(self.serial_number, "factsheet"),
                state_period=self.config.state_period,
                visualization_period=self.config.visualization_period,
                order_period=self._order_period)
            self.transport.publish_raw(
                m.topic(self.serial_number, "factsheet", self.config.manufacturer),
                orjson.dumps(sheet))

    def close(self) -> None:
        """Say OFFLINE, then disconnect cleanly (the broker then drops the will)."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            self.transport.publish(self._connection_topic,
                                   self._connection(m.ConnectionState.OFFLINE))
        self.transport.close()

    def _say_online(self) -> None:
        with self._lock:
            self.transport.publish(self._connection_topic,
                                   self._connection(m.ConnectionState.ONLINE))
        self.publish_factsheet()

    def _reconnected(self) -> None:
        # On the network thread, the broker back: a restarted broker has lost the retained
        # connection and factsheet, and one that saw the link break has published the will
        # (CONNECTIONBROKEN): say ONLINE again and publish the factsheet.
        if self._closed:
            return
        log.info("vehicle %s back on %s: ONLINE again", self.serial_number, self.config.broker)
        self._say_online()

    def _connection(self, state: m.ConnectionState) -> m.Connection:
        return m.Connection(self.headers.stamp(self.serial_number, m.Connection), state)


class LoneVehicle:
    """A lone robot as a VDA 5050 vehicle on a broker (see the module docstring).

    Args:
        runtime: the robot (started or not).
        serial_number: its serial number.
        config: the broker and protocol settings.

    Raises:
        ConfigError: a bad broker URL. BrokerUnreachable: no broker within the timeout.
    """

    def __init__(self, runtime: RobotRuntime, serial_number: str,
                 config: VehicleConfig) -> None:
        self.runtime = runtime
        period = 1.0 / runtime.config.control_rate
        epoch = dt.datetime.now(dt.UTC) - dt.timedelta(seconds=runtime.now())
        self.link = VehicleLink(serial_number, runtime.profile, config, clock=runtime.now,
                                epoch=epoch, order_period=period)
        self.agent = RobotAgent(
            serial_number, runtime, self.link.transport, {}, state_period=config.state_period,
            visualization_period=config.visualization_period, version=config.version,
            manufacturer=config.manufacturer, epoch=epoch,
            on_factsheet_request=self.link.publish_factsheet, fleet_leases=False)
        # Orders published once this returns reach the robot.
        self.link.transport.wait_subscribed(config.connect_timeout)
        self._period = period
        self._next = runtime.now()
        self._remove = runtime.add_step_listener(self._stepped)

    def _stepped(self, now: float) -> None:
        # On the robot's loop, between physics steps: the agent's commands run at once.
        if now + 1e-9 < self._next:
            return
        self._next = max(self._next + self._period, now)
        try:
            self.agent.tick(now)
        except Exception:  # one bad tick must not stop the robot's loop; it is logged
            log.exception("vehicle %s: the agent's tick failed", self.agent.serial_number)

    def close(self) -> None:
        """Stop following the broker, say OFFLINE and disconnect."""
        self._remove()
        self.link.close()
