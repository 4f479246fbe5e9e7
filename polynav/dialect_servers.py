"""The vendor dialects ``polynav run`` serves around one robot: started, announced, stopped.

Each dialect is an adapter package with a server thread of its own; this module is where
``polynav run`` composes them (and the only place that may import several adapters, to let one
contribute to another's wire: Galileo's ``/galileo/status`` on the rosbridge server).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from dataclasses import dataclass, field

from polynav.errors import PolynavError
from polynav.runtime.robot_runtime import RobotRuntime


class DialectStartError(Exception):
    """A dialect could not start: ``message`` for the user, ``exit_code`` for the process
    (1: a port taken; 2: bad input, the user's to fix)."""

    def __init__(self, message: str, exit_code: int) -> None:
        super().__init__(message)
        self.exit_code = exit_code


@dataclass
class Served:
    """A dialect that runs: what to print where it listens, and how to stop it."""

    name: str
    stop: Callable[[], None]
    lines: list[str] = field(default_factory=list)
    #: What another dialect may build on (the Galileo server's context).
    context: object = None
    #: Serial lines it serves (name -> device path), shown in ``GET /api/status``.
    links: dict[str, str] = field(default_factory=dict)
    #: Its counters of refused input, shown in ``GET /api/diagnostics``.
    diagnostics: Callable[[], dict[str, int]] | None = None


Starter = Callable[[RobotRuntime, argparse.Namespace, str, list[Served]], Served]


def start_dialects(runtime: RobotRuntime, args: argparse.Namespace, host: str) -> list[Served]:
    """Start every dialect ``args`` does not turn off, in order; on a failure the ones already
    started are stopped before :class:`DialectStartError` is raised."""
    served: list[Served] = []
    starters: list[tuple[bool, Starter]] = [
        (args.no_yunji, _yunji), (args.no_galileo, _galileo), (args.no_puwei, _puwei),
        (args.no_rosbridge, _rosbridge),
    ]
    try:
        for off, start in starters:
            if not off:
                served.append(start(runtime, args, host, served))
    except BaseException:
        stop_dialects(served)
        raise
    return served


def stop_dialects(served: list[Served]) -> None:
    """Stop them, the last started first."""
    for one in reversed(served):
        one.stop()


def _yunji(runtime: RobotRuntime, args: argparse.Namespace, host: str,
           served: list[Served]) -> Served:
    from polynav.protocols.yunji import YunjiConfig
    from polynav.protocols.yunji.server import YunjiThread

    http_port = None if args.no_yunji_http else args.yunji_http_port
    config = YunjiConfig(host=args.host, port=args.yunji_port, http_port=http_port)
    try:
        yunji = YunjiThread(runtime, config)
    except OSError as exc:
        raise DialectStartError(f"cannot listen (Yunji, ports {args.yunji_port}, {http_port}): "
                                f"{exc}", 1) from exc
    lines = [f"Yunji API tcp://{host}:{yunji.port}"]
    if yunji.http_port is not None:
        lines.append(f"Yunji HTTP http://{host}:{yunji.http_port}/api/...")
    return Served("yunji", yunji.stop, lines)


def _galileo(runtime: RobotRuntime, args: argparse.Namespace, host: str,
             served: list[Served]) -> Served:
    from polynav.protocols.galileo import GalileoConfig
    from polynav.protocols.galileo.diagnostics import diagnostics
    from polynav.protocols.galileo.server import GalileoThread

    try:
        galileo = GalileoThread(runtime, GalileoConfig(
            host=args.host, port=args.galileo_port, ws_port=args.galileo_ws_port,
            require_token=args.galileo_require_token,
            udp_port=args.galileo_udp_port or 22002,
            announce=args.galileo_udp_port != 0,
            broadcast_address=args.galileo_broadcast,
            serial=args.galileo_serial,
            modbus_port=None if args.no_galileo_modbus else args.galileo_modbus_port,
            udp_fast_port=None if args.no_galileo_udp_fast else args.galileo_udp_fast_port,
        ))
    except OSError as exc:
        raise DialectStartError(
            f"cannot listen (Galileo, ports {args.galileo_port}, {args.galileo_ws_port}, "
            f"Modbus {args.galileo_modbus_port}, UDP fast {args.galileo_udp_fast_port}, "
            f"serial {args.galileo_serial}): {exc}", 1) from exc
    except PolynavError as exc:  # a port out of range: the user's to fix
        raise DialectStartError(str(exc), 2) from exc
    lines = [f"Galileo API http://{host}:{galileo.port}/api/v1"]
    if galileo.ws_port is not None:
        lines.append(f"Galileo WebSocket ws://{host}:{galileo.ws_port}/<topic>")
    if galileo.modbus_port is not None:
        lines.append(f"Galileo Modbus TCP {host}:{galileo.modbus_port}")
    if galileo.udp_fast_port is not None:
        lines.append(f"Galileo UDP fast udp://{host}:{galileo.udp_fast_port}/<topic>")
    links = {}
    if galileo.serial_path is not None:
        lines.append(f"Galileo serial {galileo.serial_path} (115200 8N1)")
        links["galileo_serial"] = galileo.serial_path
    counters = diagnostics(galileo.server.ctx)
    return Served("galileo", galileo.stop, lines, context=galileo.server.ctx, links=links,
                  diagnostics=counters.snapshot)


def _puwei(runtime: RobotRuntime, args: argparse.Namespace, host: str,
           served: list[Served]) -> Served:
    from polynav.protocols.puwei import PuweiConfig
    from polynav.protocols.puwei.server import PuweiThread

    try:
        puwei = PuweiThread(runtime, PuweiConfig(
            host=args.host, port=args.puwei_port, discovery_port=args.puwei_discovery_port,
        ))
    except OSError as exc:
        raise DialectStartError(f"cannot listen (Puwei, port {args.puwei_port}, udp "
                                f"{args.puwei_discovery_port}): {exc}", 1) from exc
    except PolynavError as exc:  # a port out of range: the user's to fix
        raise DialectStartError(str(exc), 2) from exc
    return Served("puwei", puwei.stop, [
        f"Puwei API http://{host}:{puwei.port}/api/... (WebSocket ws://{host}:{puwei.port}"
        f"/api/ws, discovery udp {puwei.discovery_port})"])


def _rosbridge(runtime: RobotRuntime, args: argparse.Namespace, host: str,
               served: list[Served]) -> Served:
    from polynav.protocols.galileo.context import Context
    from polynav.protocols.galileo.ros_topics import add_galileo_topics
    from polynav.protocols.galileo.server import make_context
    from polynav.protocols.ros_graph import Graph
    from polynav.protocols.rosbridge import RosbridgeConfig, RosbridgeThread
    from polynav.protocols.rosbridge.androidmsg import add_androidmsg
    from polynav.protocols.rosbridge.robot_topics import add_robot_topics

    try:
        config = RosbridgeConfig(host=args.host, port=args.rosbridge_port)
    except PolynavError as exc:  # a port out of range: the user's to fix
        raise DialectStartError(str(exc), 2) from exc
    graph = Graph()
    detach = [add_robot_topics(graph, runtime), add_androidmsg(graph, runtime)]
    galileo = next((one.context for one in served if one.name == "galileo"), None)
    if galileo is None:  # /galileo/status is a Galileo robot's ROS topic: served all the same
        from polynav.protocols.galileo import GalileoConfig

        galileo = make_context(runtime, GalileoConfig(port=0, ws_port=None, announce=False))
    assert isinstance(galileo, Context)
    detach.append(add_galileo_topics(graph, galileo))
    try:
        server = RosbridgeThread(graph, runtime.clock, config)
    except OSError as exc:
        for remove in detach:
            remove()
        raise DialectStartError(f"cannot listen (rosbridge, port {args.rosbridge_port}): {exc}",
                                1) from exc

    def stop() -> None:
        for remove in detach:
            remove()
        server.stop()

    return Served("rosbridge", stop, [f"rosbridge ws://{host}:{server.port} (ROS androidmsg "
                                      "interface and the robot's topics; docs/ros.md)"])
