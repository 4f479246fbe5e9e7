"""``polynav fleet``: the fleet manager as its own process.

One :class:`~polynav.fleet.manager.FleetManager` on an MQTT broker (the robots are VDA 5050
vehicles there, from ``polynav run --robots N --broker URL --no-fleet-manager`` or any other
vehicle), its records in SQLite (``<data>/fleet.db``) or PostgreSQL (``--db
postgresql://...``, which several fleet managers may share), and its REST + WebSocket API
(:mod:`polynav.fleet_api`) on ``--host``/``--port``.

Site time is wall time × ``--speed`` from the process's start, as a ``polynav run --speed``
site's: lease durations and re-send times are in site seconds on both sides. A thread ticks
the manager every control period; uvicorn serves the API on the main thread.

At start-up a broker or a database that cannot be reached is one line on stderr and exit 1;
while running, the MQTT client reconnects with backoff and the records retry with backoff,
each saying so in the log.
"""

from __future__ import annotations

import argparse
import contextlib
import logging
import math
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # imported in run(): `polynav --help` stays fast
    from polynav.fleet.manager import FleetManager

log = logging.getLogger(__name__)

CONTROL_PERIOD = 0.1
"""The manager's tick [s of site time]."""


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser],
               default_data: Path) -> None:
    """The ``fleet`` subcommand's options (argparse only: heavy imports wait for :func:`run`)."""
    fleet = sub.add_parser(
        "fleet", help="run the fleet manager (missions, leases) for robots on an MQTT broker",
        description="Run the fleet manager: VDA 5050 master control of the robots on a broker, "
        "missions dispatched to them, leases on lift cars, doors and corridors, its records in "
        "SQLite or PostgreSQL, and its REST + WebSocket API (docs/fleet.md).")
    fleet.add_argument("--broker", required=True, metavar="mqtt://HOST[:PORT]",
                       help="the MQTT broker the robots are on")
    fleet.add_argument("--db", default=None, metavar="URL",
                       help="records database: sqlite:///PATH or postgresql://USER@HOST:PORT/DB "
                            "(default: SQLite fleet.db in the data directory)")
    fleet.add_argument("--data", type=Path, default=default_data,
                       help="site data directory, for the site's points (default: %(default)s)")
    fleet.add_argument("--host", default="127.0.0.1",
                       help="interface the API binds (default: %(default)s)")
    fleet.add_argument("--port", type=int, default=8090,
                       help="API port, 0 for any free one (default: %(default)s)")
    fleet.add_argument("--vda-version", default="2.0.0", choices=("2.0.0", "2.1.0"),
                       help="VDA 5050 version spoken (default: %(default)s)")
    fleet.add_argument("--vda-manufacturer", default="polynav",
                       help="the manufacturer in the VDA 5050 topics (default: %(default)s)")
    fleet.add_argument("--speed", type=_speed, default=1.0,
                       help="site time per wall time, as the robots' --speed "
                            "(default: %(default)s)")
    fleet.add_argument("--name", default=None,
                       help="this manager's name in the audit trail and its MQTT client id "
                            "(default: fleet-<host>-<pid>)")
    fleet.add_argument("--connect-timeout", type=_speed, default=10.0, metavar="S",
                       help="how long to try the broker and the database at start-up "
                            "(default: %(default)s s)")


def _speed(text: str) -> float:
    value = float(text)
    if not (math.isfinite(value) and value > 0.0):
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


class _Clock:
    """Site time: wall time × speed since start [s]."""

    def __init__(self, speed: float) -> None:
        self.speed = speed
        self._start = time.monotonic()

    def now(self) -> float:
        return (time.monotonic() - self._start) * self.speed


def run(args: argparse.Namespace) -> int:
    """Serve the fleet manager until SIGINT or SIGTERM; 1 if the broker, the database or the
    port cannot be had, 2 on a bad option."""
    import socket as socket_module

    import uvicorn

    from polynav.errors import PolynavError
    from polynav.fleet.manager import FleetManager
    from polynav.fleet.mqtt_transport import BrokerUnreachable, MqttTransport
    from polynav.fleet.records import FleetRecords, FleetRecordsError, RecordsConfig
    from polynav.fleet_api import FleetApiConfig, create_app
    from polynav.listen import tcp_listener
    from polynav.prompt_server import PromptServer
    from polynav.store.site_store import SiteStore

    name = args.name or f"fleet-{socket_module.gethostname()}-{os.getpid()}"
    db_url = args.db or f"sqlite:///{Path(args.data).resolve() / 'fleet.db'}"
    with contextlib.ExitStack() as stack:
        try:
            api_config = FleetApiConfig(host=args.host, port=args.port)
            store = SiteStore.open(args.data)
            stack.callback(store.close)
            records = FleetRecords.open(db_url, name=name, config=RecordsConfig(
                connect_wait=args.connect_timeout))
            stack.callback(records.close)
            transport = MqttTransport(args.broker, f"{args.vda_manufacturer}/{name}",
                                      connect_timeout=args.connect_timeout)
            stack.callback(transport.close)
        except (BrokerUnreachable, FleetRecordsError) as exc:
            print(f"polynav fleet: {' '.join(str(exc).split())}", file=sys.stderr)
            return 1
        except PolynavError as exc:
            print(f"polynav fleet: {' '.join(str(exc).split())}", file=sys.stderr)
            return 2
        levels = {f.map_name: f.level for f in store.floors()}
        manager = FleetManager(transport, records, store, levels=levels,
                               version=args.vda_version, manufacturer=args.vda_manufacturer)
        try:
            sock = tcp_listener(args.host, args.port)
        except OSError as exc:
            print(f"polynav fleet: cannot listen on {args.host}:{args.port}: {exc}",
                  file=sys.stderr)
            return 1
        stack.callback(sock.close)
        server = PromptServer(uvicorn.Config(create_app(manager, api_config), log_level="warning",
                                             lifespan="off", ws="websockets-sansio"),
                              signals=False)

        def on_signal(signum: int, _frame: object) -> None:
            log.info("signal %d", signum)
            server.should_exit = True

        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, on_signal)
        transport.wait_subscribed(args.connect_timeout)
        with _ticking(manager, _Clock(args.speed)):
            port = int(sock.getsockname()[1])
            backend = "PostgreSQL" if records.is_postgres else "SQLite"
            print(f"polynav fleet: {name} on {args.broker} (VDA 5050 {args.vda_version}, "
                  f"uagv/v2/{args.vda_manufacturer}/+), records in {backend}", flush=True)
            print(f"polynav fleet: API http://{args.host}:{port}/api (docs /docs)", flush=True)
            server.run(sockets=[sock])
    print("polynav fleet: stopped", flush=True)
    return 0


@contextlib.contextmanager
def _ticking(manager: FleetManager, clock: _Clock) -> Iterator[None]:
    """Tick ``manager`` on a thread every control period of site time until the block ends."""
    stop = threading.Event()
    period = max(0.005, CONTROL_PERIOD / clock.speed)

    def loop() -> None:
        while not stop.wait(period):
            try:
                manager.tick(clock.now())
            except Exception:  # the one broad except of the loop: one bad tick is logged
                log.exception("fleet manager tick failed")

    thread = threading.Thread(target=loop, name="fleet-manager", daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join(timeout=5.0)
