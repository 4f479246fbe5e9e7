"""A real robot reached over rosbridge: most bases already run a ROS driver that publishes
``/scan``, ``/odom``, ``/imu``, ``tf`` and ``/battery_state`` and takes ``/cmd_vel``; this
backend drives one through its rosbridge server, with no ROS installed here. It implements the
same :class:`~polynav.robot.interface.Robot` as the simulator, so the whole stack and every
dialect run on top unchanged."""

from polynav.robot.rosbridge.backend import RosbridgeBackend
from polynav.robot.rosbridge.config import BridgeConfig

__all__ = ["BridgeConfig", "RosbridgeBackend"]
