"""Where the robot's rosbridge server is, and the names its driver uses."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from polynav.errors import ConfigError


@dataclass(frozen=True, slots=True)
class BridgeConfig:
    """A bridged robot: its rosbridge URL, topic and frame names (ROS's defaults), and how the
    connection is kept.

    Attributes:
        url: ``ws://HOST:9090``.
        scan, odom, imu, battery, cmd_vel, clock, tf, tf_static: topic names.
        base_frame, laser_frame: the tf frames of the base and the lidar (the lidar's mount is
            read from the tf between them; until then the profile's mount is used).
        use_robot_clock: follow the robot's ``/clock`` (ROS ``use_sim_time``) when it publishes
            one; otherwise (or when it does not) this machine's clock.
        reconnect_min, reconnect_max: the backoff between attempts to reach the robot [s]
            (doubling from the first to the second).
        silence_timeout: a connection with no message for this long [s] is taken as dropped.
        clock_grace: how long to wait for a first ``/clock`` once odometry comes [s].
        physics_period: the backend's step [s].
    """

    url: str = "ws://127.0.0.1:9090"
    scan: str = "/scan"
    odom: str = "/odom"
    imu: str = "/imu"
    battery: str = "/battery_state"
    cmd_vel: str = "/cmd_vel"
    clock: str = "/clock"
    tf: str = "/tf"
    tf_static: str = "/tf_static"
    base_frame: str = "base_link"
    laser_frame: str = "laser"
    use_robot_clock: bool = True
    reconnect_min: float = 0.2
    reconnect_max: float = 5.0
    silence_timeout: float = 3.0
    clock_grace: float = 1.0
    physics_period: float = 0.02

    def __post_init__(self) -> None:
        if not self.url.startswith(("ws://", "wss://")):
            raise ConfigError("ros.url", f"must be a ws:// or wss:// URL, got {self.url!r}")
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if f.type == "str" and f.name != "url" and not value:
                raise ConfigError(f"ros.{f.name}", "must not be empty")
            if f.type == "float" and not value > 0:
                raise ConfigError(f"ros.{f.name}", f"must be > 0, got {value}")
        if self.reconnect_max < self.reconnect_min:
            raise ConfigError("ros.reconnect_max", "must be >= reconnect_min")

    @classmethod
    def from_mapping(cls, data: Mapping[str, Any], **overrides: Any) -> BridgeConfig:
        """From a robot profile's ``ros:`` section (unknown keys are refused).

        Raises:
            ConfigError: an unknown key or a bad value.
        """
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(data) - names)
        if unknown:
            known = ", ".join(sorted(names))
            raise ConfigError(f"ros.{unknown[0]}", f"unknown key (known: {known})")
        values = {**data, **overrides}
        try:
            return cls(**values)
        except TypeError as exc:
            raise ConfigError("ros", str(exc)) from exc
