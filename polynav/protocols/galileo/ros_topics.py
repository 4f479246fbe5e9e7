"""Galileo's ROS topics ``/galileo/status`` and ``/galileo/cmds`` on a ROS graph (the rosbridge
server).

A Galileo robot publishes ``GalileoStatus`` on ROS as well as on its WebSocket (galileo-wire-
protocols §2.1), so ROS clients of a Galileo robot subscribe to it over rosbridge. The message
is the one :func:`~polynav.protocols.galileo.status.galileo_status` builds for the WebSocket
and HTTP (one encoder), with the same context, so targets and sequence numbers agree across
the wires. ``/galileo/cmds`` takes one native command per message (§2.2), run as the serial
line runs it.
"""

from __future__ import annotations

from collections.abc import Callable

from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.diagnostics import diagnostics
from polynav.protocols.galileo.native.control import native_control
from polynav.protocols.galileo.native.ros_message import NATIVE_CMDS_TYPE, decode_native_cmds
from polynav.protocols.galileo.status import galileo_status
from polynav.protocols.ros_graph import Graph, Message, RosError, Subscription, Topic
from polynav.runtime.step_hooks import every

#: The topic and its type as Galileo's ROS package names them (galileo-wire-protocols §2.1).
STATUS = Topic("/galileo/status", "galileo_msg/GalileoStatus")
#: Messages per second of the runtime's clock, as on the Galileo WebSocket.
STATUS_RATE = 10.0



def add_galileo_topics(graph: Graph, ctx: Context) -> Callable[[], None]:
    """Declare ``/galileo/status`` on ``graph`` and publish it at :data:`STATUS_RATE` of the
    runtime's clock, and take ``/galileo/cmds``; returns the function that stops publishing."""
    graph.add_topic(STATUS)

    def on_cmds(message: Message) -> None:
        try:
            payload = decode_native_cmds(message)
        except ValueError as exc:
            diagnostics(ctx).count("ros.bad_message")
            raise RosError(f"/galileo/cmds: {exc}") from None
        native_control(ctx).apply(payload)

    graph.add_subscription(Subscription("/galileo/cmds", NATIVE_CMDS_TYPE, on_cmds))
    return every(ctx.runtime, 1.0 / STATUS_RATE,
                 lambda: graph.publish(STATUS.name, galileo_status(ctx)))
