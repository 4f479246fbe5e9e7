"""The ``polynav`` command line.

Benchmarks live in the repository's ``benchmarks/`` folder (STYLE R12); ``polynav bench AREA`` is a
thin front that loads ``benchmarks/AREA.py`` and calls its ``main(argv)``.
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import importlib.util
import logging
import math
import os
import signal
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from polynav import users_cli
from polynav.errors import PolynavError
from polynav.house import fleet_process
from polynav.mapping import cli as mapping_cli
from polynav.site import PointKind
from polynav.worlds import cli as world_cli

if TYPE_CHECKING:  # imported lazily at run time: `polynav --help` stays fast
    from polynav.robot.profile import RobotProfile
    from polynav.robot.rosbridge import RosbridgeBackend
    from polynav.store.site_store import SiteStore
    from polynav.worlds.world import World

log = logging.getLogger(__name__)

EXIT_BAD_INPUT = 2

BENCH_AREAS = ("planner", "sim", "api", "slam", "nav", "clutter", "fleet")
_BENCH_FILES = {
    "planner": "planner.py", "sim": "simulation.py", "api": "api.py", "slam": "slam.py",
    "nav": "nav.py", "clutter": "clutter.py", "fleet": "fleet.py",
}


def _benchmarks_dir() -> Path:
    return Path(__file__).resolve().parent.parent / "benchmarks"


def _run_bench(area: str, argv: list[str]) -> int:
    path = _benchmarks_dir() / _BENCH_FILES[area]
    if not path.is_file():
        print(f"polynav bench: {path} not found (benchmarks run from a source checkout)",
              file=sys.stderr)
        return 2
    spec = importlib.util.spec_from_file_location(f"polynav_bench_{area}", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return int(module.main([*argv]) or 0)


def default_data_dir() -> Path:
    """Where ``polynav run`` keeps its site by default: ``$XDG_DATA_HOME/polynav`` (usually
    ``~/.local/share/polynav``), so a checkout stays clean and the site survives a new clone."""
    base = os.environ.get("XDG_DATA_HOME") or str(Path.home() / ".local" / "share")
    return Path(base) / "polynav"


def _positive_speed(text: str) -> float:
    value = float(text)
    if not (math.isfinite(value) and value > 0.0):
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def _calendar_epoch(text: str) -> datetime.datetime:
    try:
        when = datetime.datetime.fromisoformat(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"not a date-time: {exc}") from None
    if when.tzinfo is not None:
        raise argparse.ArgumentTypeError("a local date-time, without a time zone")
    return when


def _dispatch_server(text: str) -> tuple[str, str]:
    server_id, sep, url = text.partition("=")
    if not (sep and server_id.strip() and url.strip()):
        raise argparse.ArgumentTypeError(f"give ID=URL, got {text!r}")
    return server_id.strip(), url.strip()


def _run(args: argparse.Namespace) -> int:
    """Serve the native API around the simulated robot until SIGINT or SIGTERM."""
    if args.robots is not None:  # a building of N robots: polynav/house/serve.py
        from polynav.house import serve

        return serve.run(args)
    import uvicorn

    from polynav.api import ApiConfig, create_app
    from polynav.api.auth_gate import login_refusal
    from polynav.dialect_servers import DialectStartError, start_dialects, stop_dialects
    from polynav.listen import tcp_listener
    from polynav.prompt_server import PromptServer
    from polynav.robot.profile import load_profile
    from polynav.runtime.config import RuntimeConfig
    from polynav.runtime.robot_runtime import RobotRuntime
    from polynav.store.site_store import SiteStore
    from polynav.worlds import load_world

    # uvicorn catches SIGINT/SIGTERM while serving, then re-raises them to the handlers it
    # found; these note them, so the runtime and store below still close cleanly. A signal that
    # comes during start-up, before uvicorn serves, skips serving altogether.
    stop_requested: list[int] = []
    server: uvicorn.Server | None = None

    def on_signal(signum: int, _frame: object) -> None:
        log.info("signal %d", signum)
        stop_requested.append(signum)
        if server is not None:
            server.should_exit = True

    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, on_signal)

    api_config = ApiConfig(host=args.host, port=args.port)
    try:
        world = load_world(args.world)
        profile = load_profile(args.robot) if args.robot is not None else world.robot
    except PolynavError as exc:
        # A bad profile or world is the user's to fix: one line naming the field, exit 2.
        print(f"polynav run: {' '.join(str(exc).split())}", file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        runtime_config = RuntimeConfig(speed=args.speed, seed=args.seed,
                                       people=not args.no_people,
                                       automations=args.automations,
                                       task_callback_hosts=tuple(args.task_callback_host),
                                       dispatch_servers=tuple(args.dispatch_server),
                                       calendar_epoch=args.calendar_epoch)
    except PolynavError as exc:
        print(f"polynav run: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    store = SiteStore.open(args.data, seed_world=world)
    try:
        refusal = login_refusal(api_config, store)
        if refusal is not None:  # before binding anything
            print(f"polynav run: {refusal}", file=sys.stderr)
            return EXIT_BAD_INPUT
        for warning in site_mismatches(store, world):
            print(f"polynav run: warning: {warning}", file=sys.stderr)
        backend = None
        if args.robot_bridge is not None:
            backend = _robot_bridge(args.robot_bridge, profile)
            if backend is None:
                return 1
            runtime = RobotRuntime.bridged(store, backend, config=runtime_config,
                                           profile=profile)
        else:
            runtime = RobotRuntime.simulated(store, world, config=runtime_config, profile=profile)
        if args.mapless:
            runtime.start_mapless()  # goals are then poses in the odometry frame
        app = create_app(runtime, api_config)
        try:
            sock = tcp_listener(api_config.host, api_config.port)
        except OSError as exc:
            print(f"polynav run: cannot listen on {api_config.host}:{api_config.port}: {exc}",
                  file=sys.stderr)
            return 1
        host, port = sock.getsockname()[:2]
        server = PromptServer(
            uvicorn.Config(app, log_level="warning", lifespan="off", ws="websockets-sansio")
        )
        runtime.start()
        vehicle = embedded = None
        try:
            if args.broker is not None:  # a VDA 5050 vehicle: polynav/fleet/vehicle.py
                from polynav.fleet.vehicle import LoneVehicle, config_from_args
                from polynav.house import broker

                try:
                    embedded = broker.resolve(args)  # --broker embedded: one in this process
                    vehicle = LoneVehicle(runtime, args.vda_serial, config_from_args(args))
                except PolynavError as exc:
                    print(f"polynav run: {exc}", file=sys.stderr)
                    return 1
            try:
                served = start_dialects(runtime, args, host)
            except DialectStartError as exc:
                print(f"polynav run: {exc}", file=sys.stderr)
                return exc.exit_code
            for one in served:
                app.state.links.update(one.links)
                if one.diagnostics is not None:
                    app.state.diagnostics[one.name] = one.diagnostics
            base = f"http://{host}:{port}"
            if backend is not None:
                print(f"polynav: driving robot {runtime.profile.name!r} over rosbridge at "
                      f"{args.robot_bridge}, data in {Path(args.data).resolve()}", flush=True)
            else:
                print(f"polynav: simulating robot {runtime.profile.name!r} in world "
                      f"{world.name!r} at {args.speed:g}x, data in {Path(args.data).resolve()}",
                      flush=True)
            print(f"polynav: native API {base}/api  (docs {base}/docs, "
                  f"WebSocket ws://{host}:{port}/api/ws)", flush=True)
            for one in served:
                for line in one.lines:
                    print(f"polynav: {line}", flush=True)
            if embedded is not None:
                print(f"polynav: {broker.banner(embedded)}", flush=True)
            if vehicle is not None:
                print(f"polynav: VDA 5050 {args.vda_version} vehicle on {args.broker} as "
                      f"uagv/v2/{args.vda_manufacturer}/{args.vda_serial}/", flush=True)
            print("polynav: Ctrl-C to stop", flush=True)
            if args.open:
                from polynav.web import open_console_when_serving

                running = server
                open_console_when_serving(lambda: running.started, f"{base}/")
            try:
                if not stop_requested:
                    server.run(sockets=[sock])
            finally:
                stop_dialects(served)
        finally:
            if vehicle is not None:
                vehicle.close()
            if embedded is not None:
                embedded.close()
            runtime.stop()
            if backend is not None:
                backend.close()
            sock.close()
    finally:
        store.close()
    print("polynav: stopped", flush=True)
    return 0


#: How long ``polynav run --robot-bridge`` waits for the robot's first odometry [s].
BRIDGE_READY_TIMEOUT = 30.0


def _robot_bridge(url: str, profile: RobotProfile | None) -> RosbridgeBackend | None:
    """Connect to the robot's rosbridge and wait for its odometry; ``None`` (said on stderr)
    when it does not come."""
    from polynav.geometry import Pose2D
    from polynav.robot.rosbridge import BridgeConfig, RosbridgeBackend

    names = profile.ros if profile is not None and profile.ros is not None else BridgeConfig()
    try:
        config = dataclasses.replace(names, url=url)
    except PolynavError as exc:
        print(f"polynav run: --robot-bridge: {exc}", file=sys.stderr)
        return None
    lidar = profile.lidar if profile is not None else None
    mount = Pose2D(lidar.x, lidar.y, lidar.theta) if lidar is not None else Pose2D()
    backend = RosbridgeBackend(config, laser_mount=mount)
    print(f"polynav: waiting for the robot's odometry on {url} ...", flush=True)
    if not backend.wait_ready(BRIDGE_READY_TIMEOUT):
        backend.close()
        print(f"polynav run: no odometry from {url}{config.odom} within "
              f"{BRIDGE_READY_TIMEOUT:g} s (is its rosbridge server up, and its driver?)",
              file=sys.stderr)
        return None
    return backend


def site_mismatches(store: SiteStore, world: World) -> list[str]:
    """Why the site in ``store`` may not be ``world``'s: a data directory is seeded from a world
    once, so ``polynav run --world B`` on a directory seeded from world A simulates B while the
    robot navigates on A's maps. A map edited since (SLAM, import) shows here too, so it is a
    warning, not a refusal."""
    maps = {record.name: record for record in store.maps()}
    notes = []
    for floor in world.floors:
        record = maps.get(floor.map_name)
        info = floor.map.info
        if record is None:
            notes.append(f"the site in {store.data_dir} has no map {floor.map_name!r} of world "
                         f"{world.name!r}; pass --data NEW_FOLDER to start a site from it")
        elif (record.width, record.height) != (info.width, info.height) or not math.isclose(
            record.resolution, info.resolution
        ):
            notes.append(
                f"map {floor.map_name!r} of the site in {store.data_dir} is {record.width} x "
                f"{record.height} at {record.resolution:g} m, world {world.name!r} has "
                f"{info.width} x {info.height} at {info.resolution:g} m: the robot navigates on "
                "the site's map (pass --data NEW_FOLDER to start a site from the world)"
            )
    return notes


def _open_store(args: argparse.Namespace) -> SiteStore:
    from polynav.store.site_store import SiteStore
    from polynav.worlds import load_world

    return SiteStore.open(args.data, seed_world=load_world(args.world))


def _map_command(args: argparse.Namespace) -> int:
    from polynav.maps import ros_map

    store = _open_store(args)
    try:
        if args.map_command == "list":
            for record in store.maps():
                print(f"{record.name}\tfloor={record.floor}\t{record.width}x{record.height} "
                      f"@ {record.resolution:g} m\torigin=({record.origin.x:g}, "
                      f"{record.origin.y:g}, {record.origin.theta:g})")
        elif args.map_command == "import":
            grid = ros_map.load_map(args.yaml)
            record = store.save_map(args.name or Path(args.yaml).stem, grid, floor=args.floor)
            print(f"imported map {record.name!r} ({record.width}x{record.height})")
        else:
            ros_map.save_map(store.load_map(args.name), args.yaml)
            print(f"exported map {args.name!r} to {args.yaml}")
    finally:
        store.close()
    return 0


def _points_command(args: argparse.Namespace) -> int:
    from polynav.geometry import Pose2D
    from polynav.site import Point, PointKind

    store = _open_store(args)
    try:
        if args.points_command == "list":
            for p in store.points(map_name=args.map):
                print(f"{p.map_name}\t{p.name}\t{p.kind.value}\t"
                      f"{p.pose.x:.3f}\t{p.pose.y:.3f}\t{p.pose.theta:.3f}")
        elif args.points_command == "add":
            point = store.add_point(Point(args.name, args.map, Pose2D(args.x, args.y, args.theta),
                                          PointKind(args.kind), args.number))
            print(f"added point {point.name!r} on map {point.map_name!r}")
        else:
            point = store.find_point(args.name, map_name=args.map)
            store.delete_point(point.map_name, point.name)
            print(f"removed point {point.name!r} from map {point.map_name!r}")
    finally:
        store.close()
    return 0


def _data_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--data", type=Path, default=default_data_dir(),
                        help="site data directory (default: %(default)s)")
    parser.add_argument("--world", default="demo",
                        help="built-in world name or folder path; seeds a fresh data directory")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="polynav", description=__doc__.splitlines()[0])
    parser.add_argument("-v", "--verbose", action="count", default=0, help="more logging")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser(
        "run",
        help="serve the native API around the simulated robot",
        description="Start the simulated robot on a site (seeded from the world on first use) and "
        "serve the native REST + WebSocket API until Ctrl-C or SIGTERM.",
    )
    _data_options(run)
    run.add_argument("--host", default="127.0.0.1", help="interface to bind (default: %(default)s)")
    run.add_argument("--port", type=int, default=8000,
                     help="native API port, 0 for any free one (default: %(default)s)")
    run.add_argument("--speed", type=_positive_speed, default=1.0,
                     help="simulated time factor (default: %(default)s)")
    run.add_argument("--seed", type=int, default=0, help="seed of every simulated noise source")
    run.add_argument("--calendar-epoch", type=_calendar_epoch, default=None,
                     help="the local date-time (YYYY-MM-DDTHH:MM[:SS]) that simulated time 0 "
                     "stands for, for schedules; default: now")
    run.add_argument("--no-people", action="store_true", help="no walkers in the simulation")
    run.add_argument("--open", action="store_true",
                     help="open the web console (the native API's /) in the browser")
    run.add_argument("--automations", action="store_true",
                     help="let automation tasks (user programs) run, each in its own limited "
                          "process (default: off)")
    run.add_argument("--task-callback-host", action="append", default=[], metavar="HOST",
                     help="a host name or IP network a task's callback_action may call beside "
                          "loopback (repeat for more; default: loopback only)")
    run.add_argument("--dispatch-server", action="append", default=[], metavar="ID=URL",
                     type=_dispatch_server,
                     help="a dispatch server tasks exchange maps with (upload_map_action, "
                          "download_map_action), on a host a callback may reach (repeat)")
    run.add_argument("--mapless", action="store_true",
                     help="navigate without a map from the start: goals are poses in the odometry "
                          "frame (POST /api/navigation/goal with x, y, theta)")
    run.add_argument("--robot", default=None,
                     help="robot profile: a robot.yaml or a built-in name (demo, delivery, "
                          "research-base); default: the world's robot, else demo")
    run.add_argument("--robots", type=int, default=None,
                     help="simulate N robots in one building, robot i on every port + i "
                     "(default: one robot)")
    run.add_argument("--broker", default=None, metavar="mqtt://HOST[:PORT]|embedded",
                     help="be a VDA 5050 vehicle on this MQTT broker, each robot one client "
                          "(with --robots, the fleet's master control too; docs/fleet.md); "
                          "'embedded' starts one in this process")
    run.add_argument("--broker-port", type=int, default=1883,
                     help="the embedded broker's port on 127.0.0.1, 0 for any free one "
                          "(default: %(default)s)")
    run.add_argument("--no-fleet-manager", action="store_true",
                     help="with --robots and --broker: vehicles only, for a `polynav fleet` "
                          "on the same broker")
    run.add_argument("--vda-version", default="2.0.0", choices=("2.0.0", "2.1.0"),
                     help="VDA 5050 version spoken on the broker (default: %(default)s)")
    run.add_argument("--vda-manufacturer", default="polynav",
                     help="the manufacturer in the VDA 5050 topics (default: %(default)s)")
    run.add_argument("--vda-serial", default="robot1",
                     help="a lone robot's VDA 5050 serial number (default: %(default)s; with "
                          "--robots, robot1..robotN)")
    run.add_argument("--connect-timeout", type=float, default=10.0, metavar="S",
                     help="with --broker: how long to try the broker at start-up before "
                          "giving up (default: %(default)s s)")
    run.add_argument("--vda-visualization-rate", type=float, default=1.0, metavar="HZ",
                     help="visualization messages per second, 0 for none (default: %(default)s)")
    run.add_argument("--yunji-port", type=int, default=31001,
                     help="Yunji TCP API port, 0 for any free one (default: %(default)s)")
    run.add_argument("--no-yunji", action="store_true", help="do not serve the Yunji TCP API")
    run.add_argument("--yunji-http-port", type=int, default=8808,
                     help="Yunji legacy HTTP port, 0 for any free one (default: %(default)s)")
    run.add_argument("--galileo-port", type=int, default=3546,
                     help="Galileo HTTP API port (default: %(default)s)")
    run.add_argument("--galileo-ws-port", type=int, default=3547,
                     help="Galileo WebSocket port (default: %(default)s)")
    run.add_argument("--no-galileo", action="store_true", help="do not serve the Galileo API")
    run.add_argument("--galileo-udp-port", type=int, default=22002,
                     help="port the Galileo discovery announcement is sent to; "
                          "0: no announcements (default: %(default)s)")
    run.add_argument("--galileo-broadcast", default="127.255.255.255",
                     help="where Galileo discovery announcements go: loopback unless a LAN "
                          "broadcast address is given (default: %(default)s)")
    run.add_argument("--galileo-serial", metavar="PATH|pty", default=None,
                     help="serve Galileo's serial protocol on a serial device (/dev/ttyUSB0, "
                          "115200 8N1) or on a new pseudo-terminal ('pty'; its path is printed "
                          "and in GET /api/status 'links')")
    run.add_argument("--galileo-modbus-port", type=int, default=3551,
                     help="Galileo Modbus TCP port, 0 for any free one (default: %(default)s)")
    run.add_argument("--no-galileo-modbus", action="store_true",
                     help="do not serve Galileo's Modbus TCP")
    run.add_argument("--galileo-udp-fast-port", type=int, default=3547,
                     help="Galileo UDP fast protocol (the WebSocket topics over UDP) port, 0 for "
                          "any free one (default: %(default)s/udp)")
    run.add_argument("--no-galileo-udp-fast", action="store_true",
                     help="do not serve Galileo's UDP fast protocol")
    run.add_argument("--galileo-require-token", action="store_true",
                     help="check Galileo tokens whatever config.json's no_token_check says")
    run.add_argument("--no-yunji-http", action="store_true",
                     help="do not serve the Yunji legacy HTTP form")
    run.add_argument("--puwei-port", type=int, default=8080,
                     help="Puwei HTTP API and WebSocket port, 0 for any free one "
                          "(default: %(default)s)")
    run.add_argument("--no-puwei", action="store_true", help="do not serve the Puwei API")
    run.add_argument("--rosbridge-port", type=int, default=9090,
                     help="rosbridge v2 WebSocket: the ROS androidmsg interface and the robot's "
                          "topics (default: %(default)s; 0: any free port)")
    run.add_argument("--no-rosbridge", action="store_true", help="do not serve rosbridge")
    run.add_argument("--robot-bridge", metavar="ws://HOST:9090", default=None,
                     help="drive a real robot through its rosbridge server instead of "
                          "simulating one (topic names from the profile's ros: section)")
    run.add_argument("--puwei-discovery-port", type=int, default=9999,
                     help="Puwei UDP discovery port (unicast and group 224.0.0.1, joined on "
                          "loopback), 0 for any free one (default: %(default)s)")
    maps = sub.add_parser("map", help="list, import or export ROS maps of the site",
                          description="Manage the site's maps (ROS map_server YAML + image).")
    map_sub = maps.add_subparsers(dest="map_command", required=True)
    map_list = map_sub.add_parser("list", help="list the maps", description="List the maps.")
    _data_options(map_list)
    map_import = map_sub.add_parser("import", help="import a ROS map (YAML + image)",
                                    description="Add or replace a map from a ROS map YAML.")
    map_import.add_argument("yaml", help="the map's YAML file")
    map_import.add_argument("--name", help="map name (default: the YAML file's stem)")
    map_import.add_argument("--floor", help="the floor the map belongs to")
    _data_options(map_import)
    map_export = map_sub.add_parser("export", help="export a map as ROS files",
                                    description="Write a map as ROS map YAML + PNG.")
    map_export.add_argument("name", help="the map to export")
    map_export.add_argument("yaml", help="the YAML file to write (the PNG goes beside it)")
    _data_options(map_export)
    points = sub.add_parser("points", help="list, add or remove named points",
                            description="Manage the site's named points.")
    points_sub = points.add_subparsers(dest="points_command", required=True)
    points_list = points_sub.add_parser("list", help="list the points",
                                        description="List the points (map, name, kind, x, y, "
                                        "theta).")
    points_list.add_argument("--map", help="only this map's points")
    _data_options(points_list)
    points_add = points_sub.add_parser("add", help="add a point", description="Add a point.")
    points_add.add_argument("name")
    points_add.add_argument("--map", required=True, help="the point's map")
    points_add.add_argument("--x", type=float, required=True, help="[m]")
    points_add.add_argument("--y", type=float, required=True, help="[m]")
    points_add.add_argument("--theta", type=float, default=0.0, help="[rad]")
    points_add.add_argument("--kind", default="general", choices=[k.value for k in PointKind])
    points_add.add_argument("--number", type=int, default=None)
    _data_options(points_add)
    points_rm = points_sub.add_parser("rm", help="remove a point", description="Remove a point.")
    points_rm.add_argument("name")
    points_rm.add_argument("--map", help="the point's map, when the name is on several maps")
    _data_options(points_rm)
    mapping_cli.add_parser(sub)
    world_cli.add_parser(sub)
    users_cli.add_parser(sub, default_data_dir())
    fleet_process.add_parser(sub, default_data_dir())
    bench = sub.add_parser(
        "bench",
        help="run a benchmark (planner, sim, api, slam, nav, fleet); extra arguments go to the "
        "benchmark",
        description="Run a benchmark from benchmarks/. Pass --help after the area for its options.",
    )
    bench.add_argument("area", choices=BENCH_AREAS)
    bench.add_argument("args", nargs=argparse.REMAINDER, help="arguments for the benchmark")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(list(sys.argv[1:] if argv is None else argv))
    logging.basicConfig(
        level=logging.WARNING - 10 * min(args.verbose, 2),
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
    )
    if args.command == "bench":
        return _run_bench(args.area, args.args)
    if args.command == "run":
        return _run(args)
    if args.command == "fleet":
        return fleet_process.run(args)
    try:
        if args.command == "map":
            return _map_command(args)
        if args.command == "points":
            return _points_command(args)
        if args.command == "users":
            return users_cli.main(args)
        if args.command == "slam":
            return mapping_cli.main(args)
        if args.command == "world":
            return world_cli.main(args)
    except PolynavError as exc:
        print(f"polynav {args.command}: {exc}", file=sys.stderr)
        return 1
    parser.error(f"unknown command {args.command}")
    return 2
