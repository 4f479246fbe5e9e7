"""``polynav run --robots N``: a building of N simulated robots, each with its own addresses.

With ``--broker mqtt://...`` each robot is a VDA 5050 vehicle on that broker and the fleet
manager another client (:mod:`polynav.fleet.vehicle`), or, with ``--no-fleet-manager``, none:
a ``polynav fleet`` elsewhere runs the fleet; without a broker, they share an in-process
transport. Robot ``i`` (0-based) serves its native API on ``--port + i`` and each dialect on
that dialect's port ``+ i``, as a building of N vendor robots has N addresses; a port of 0
stays 0 (each server on a free port). Every robot's ``GET /api/fleet`` lists them all. The
servers share one asyncio loop on the main thread; the building's loop thread steps the robots.
"""

from __future__ import annotations

import argparse
import asyncio
import logging
import signal
import socket
import sys
from pathlib import Path

import uvicorn

from polynav.api import ApiConfig, create_app
from polynav.errors import InvalidRequest, PolynavError
from polynav.fleet.mqtt_transport import BrokerUnreachable
from polynav.fleet.vehicle import config_from_args
from polynav.house import broker
from polynav.house.building import Building
from polynav.listen import tcp_listener
from polynav.prompt_server import PromptServer
from polynav.robot.profile import load_profile
from polynav.runtime.config import RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world

log = logging.getLogger(__name__)


def _offset(port: int, i: int) -> int:
    return 0 if port == 0 else port + i


def run(args: argparse.Namespace) -> int:
    """Serve N robots until SIGINT or SIGTERM; 2 on a bad robot count, 1 on a busy port."""
    from polynav.protocols.yunji import YunjiConfig
    from polynav.protocols.yunji.server import YunjiThread

    try:
        if args.mapless:
            raise InvalidRequest("mapless", "--mapless runs one robot: leave out --robots")
        world = load_world(args.world)
        profile = load_profile(args.robot) if args.robot is not None else world.robot
    except PolynavError as exc:
        print(f"polynav run: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    store = SiteStore.open(args.data, seed_world=world)
    from polynav.api.auth_gate import login_refusal

    refusal = login_refusal(ApiConfig(host=args.host, port=0), store)
    if refusal is not None:  # before binding anything
        print(f"polynav run: {refusal}", file=sys.stderr)
        store.close()
        return 2
    servers: list[PromptServer] = []
    stop_requested: list[int] = []

    def on_signal(signum: int, _frame: object) -> None:
        log.info("signal %d", signum)
        stop_requested.append(signum)
        for server in servers:
            server.should_exit = True

    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, on_signal)
    embedded = None
    try:
        try:
            embedded = broker.resolve(args)  # --broker embedded: one in this process
            building = Building(
                store, world, robots=args.robots,
                config=RuntimeConfig(speed=args.speed, seed=args.seed, people=not args.no_people,
                                     automations=args.automations,
                                     task_callback_hosts=tuple(args.task_callback_host),
                                     dispatch_servers=tuple(args.dispatch_server),
                                     calendar_epoch=args.calendar_epoch),
                profile=profile,
                vehicles=config_from_args(args) if args.broker is not None else None,
                fleet_manager=not getattr(args, "no_fleet_manager", False),
            )
        except (BrokerUnreachable, broker.BrokerStartError) as exc:
            print(f"polynav run: {exc}", file=sys.stderr)
            return 1
        except PolynavError as exc:
            print(f"polynav run: {exc}", file=sys.stderr)
            return 2
        sockets: list[socket.socket] = []
        yunjis: list[YunjiThread] = []
        try:
            for i, (serial, runtime) in enumerate(zip(building.serials, building.runtimes,
                                                      strict=True)):
                port = _offset(args.port, i)
                try:
                    sock = tcp_listener(args.host, port)
                except OSError as exc:
                    print(f"polynav run: cannot listen on {args.host}:{port} ({serial}): {exc}",
                          file=sys.stderr)
                    return 1
                sockets.append(sock)
                ports = {"native": int(sock.getsockname()[1])}
                if not args.no_yunji:
                    http_port = None if args.no_yunji_http else _offset(args.yunji_http_port, i)
                    config = YunjiConfig(host=args.host, port=_offset(args.yunji_port, i),
                                         http_port=http_port)
                    try:
                        yunji = YunjiThread(runtime, config)
                    except OSError as exc:
                        print(f"polynav run: cannot listen (Yunji of {serial}): {exc}",
                              file=sys.stderr)
                        return 1
                    yunjis.append(yunji)
                    ports["yunji"] = yunji.port
                    if yunji.http_port is not None:
                        ports["yunji_http"] = yunji.http_port
                building.ports[serial] = ports
                app = create_app(runtime, ApiConfig(host=args.host, port=port),
                                 fleet=building.entries)
                servers.append(PromptServer(uvicorn.Config(app, log_level="warning", lifespan="off",
                                                           ws="websockets-sansio"),
                                            signals=False))
            building.start()
            print(f"polynav: simulating world {world.name!r} with {args.robots} robots at "
                  f"{args.speed:g}x, data in {Path(args.data).resolve()}", flush=True)
            for serial, start in zip(building.serials, building.starts, strict=True):
                ports = building.ports[serial]
                line = (f"polynav: {serial} at {start.map_name}/{start.name}: native API "
                        f"http://{args.host}:{ports['native']}/api")
                if "yunji" in ports:
                    line += f"  Yunji tcp://{args.host}:{ports['yunji']}"
                print(line, flush=True)
            if embedded is not None:
                print(f"polynav: {broker.banner(embedded)}", flush=True)
            if args.broker is not None:
                print(f"polynav: VDA 5050 {args.vda_version} vehicles on {args.broker} under "
                      f"uagv/v2/{args.vda_manufacturer}/<robot>/", flush=True)
            print("polynav: Ctrl-C to stop", flush=True)
            if args.open and servers:  # the first robot's console; it lists the others
                from polynav.web import open_console_when_serving

                first = building.ports[building.serials[0]]["native"]
                open_console_when_serving(lambda: servers[0].started,
                                          f"http://{args.host}:{first}/")
            if not stop_requested:
                asyncio.run(_serve_all(servers, sockets))
        finally:
            for yunji in yunjis:
                yunji.stop()
            building.close()
            for sock in sockets:
                sock.close()
    finally:
        if embedded is not None:
            embedded.close()
        store.close()
    print("polynav: stopped", flush=True)
    return 0


async def _serve_all(servers: list[PromptServer], sockets: list[socket.socket]) -> None:
    await asyncio.gather(*(server.serve(sockets=[sock])
                           for server, sock in zip(servers, sockets, strict=True)))
