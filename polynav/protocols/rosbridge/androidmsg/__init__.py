"""The ROS1 androidmsg navigation interface (ros1-nav-iface) on a ROS graph: the status topics,
the goal and stop commands and the seventeen services, over the runtime's services. The
sensor streams of the same interface (``/map``, ``/tracked_pose``, ``/imu/data``,
``/raw_odom``, ``/scan``) and ``/cmd_vel`` are :mod:`polynav.protocols.rosbridge.robot_topics`.
"""

from __future__ import annotations

from collections.abc import Callable

from polynav.protocols.ros_graph import Graph
from polynav.protocols.rosbridge.androidmsg.editing import Editing
from polynav.protocols.rosbridge.androidmsg.maps import Maps
from polynav.protocols.rosbridge.androidmsg.navigation import Navigation
from polynav.protocols.rosbridge.androidmsg.status import StatusTopics
from polynav.protocols.rosbridge.androidmsg.system import System
from polynav.runtime.robot_runtime import RobotRuntime


def add_androidmsg(graph: Graph, runtime: RobotRuntime,
                   robot_id: str = "polynav") -> Callable[[], None]:
    """Declare the interface on ``graph`` over ``runtime``; returns the function that
    detaches it from the runtime."""
    status = StatusTopics(graph, runtime)
    status.declare()
    Navigation(runtime, status).declare(graph)
    Maps(runtime, status).declare(graph)
    Editing(runtime, status).declare(graph)
    System(runtime, robot_id).declare(graph)
    remove = runtime.add_step_listener(status.on_step)

    def detach() -> None:
        remove()
        status.close()

    return detach
