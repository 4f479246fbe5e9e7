"""Fleet benchmark over MQTT: robots in several processes on one real broker, missions over MQTT.

``polynav bench fleet --transport mqtt --robots N --processes P [--agents full|kinematic]``
(argument parsing in ``benchmarks/fleet.py``) starts a real Mosquitto on a free loopback port,
forks P worker processes and dispatches random missions from this process (the coordinator):

- ``--agents full`` (default): each worker is a :class:`~polynav.house.building.Building` with
  its share of the robots, every robot a VDA 5050 vehicle on the broker, and no master control
  of its own; each worker's scene shows the other workers' robots as moving bodies
  (:mod:`polynav.house.remote_robots`) at the poses their visualization messages give, so the
  lidars see them and a robot moving into one is stopped and counted. The workers' walkers are
  simulated in each worker (the same routes; each stops for every robot, local or remote).
- ``--agents kinematic`` (the *light mode*): each worker runs its share as
  :class:`~polynav.fleet.kinematic_vehicle.KinematicVehicle` s on one shared MQTT connection
  (no sensors, no localization, no zones: straight lines, a lift a fixed wait), to load the
  master control and the broker with many more.

Every process runs on one site clock: site time = ``--speed`` x (wall time since a common
start), the workers' loops catching up when they fall behind (the real-time factor says whether
they kept the pace). The coordinator runs the fleet manager ``polynav fleet`` runs
(:class:`~polynav.fleet.manager.FleetManager`: its records in SQLite, its master control's
lease book deciding through them, on one shared MQTT connection) on it, ticked every 20 ms;
missions are posted to it (:func:`post_mission`, as ``POST /api/missions``), one per robot
kept posted, at most one per 20 robots per tick (a starting fleet of 1,000 does not post 1,000
missions in one burst), and the manager queues them and dispatches each to the best robot.
``--broker-restart-at S`` kills the broker at site time S and starts it again.

Figures: missions per hour, success, the manager's queue wait (posted to dispatched, site time),
lease waits, order latency (the order's publication to the
first state that acknowledges it: names the order, or rejects it) p50/p99, broker messages/s
(Mosquitto's ``$SYS`` counters), CPU per robot, real-time factor, collisions (robot pairs
counted once across the processes), lost state messages (gaps in each robot's headerId), and how
stale the remote robots' poses may be.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime as dt
import itertools
import math
import multiprocessing as mp
import os
import shutil
import socket
import subprocess
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from multiprocessing.synchronize import Event
from pathlib import Path
from queue import Empty
from typing import Any

import numpy as np
import orjson
import psutil

from polynav.fleet import messages as m
from polynav.fleet.kinematic_vehicle import KinematicConfig, KinematicVehicle
from polynav.fleet.manager import FleetManager, FleetManagerConfig
from polynav.fleet.master_control import MasterControl
from polynav.fleet.mqtt_transport import MqttTransport
from polynav.fleet.records import FleetRecords
from polynav.fleet.shared_client import LocalInbox, SharedClient
from polynav.fleet.vehicle import VehicleConfig
from polynav.geometry import Pose2D
from polynav.house.building import Building
from polynav.house.remote_robots import RemoteRobots
from polynav.runtime.config import RuntimeConfig
from polynav.site import Point, PointKind
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from polynav.worlds.world import World

BUDGET_LATENCY_P99 = 0.100  # [s], 1,000 kinematic agents
STATE_PERIOD = 1.0  # [s of site time] a full robot's longest between two states
DISPATCH_SHARE = 20  # at most 1/20 of the robots are sent an order per coordinator tick (20 ms)
ANSWER_EVERY = 50  # a light worker answers orders between every this many vehicles' moves
MISSION_PERIOD = 60.0  # [s of site time] by default, one mission per robot per this posted
MAX_LEAD = 1.0  # [s of site time] a worker may run ahead of the slowest other one
CONTACT_WINDOW = 2.0  # [s of site time]: one pair's contacts closer than this are one collision
READY_TIMEOUT = 600.0  # [s of wall time] for the workers to build their share

Starts = Callable[[SiteStore, list[str], int], list[Point]]


# -- the broker ----------------------------------------------------------------------------------


class Broker:
    """Mosquitto on a free loopback port, ``$SYS`` counters every second."""

    def __init__(self, workdir: Path) -> None:
        binary = shutil.which("mosquitto") or shutil.which(
            "mosquitto", path="/usr/sbin:/usr/local/sbin")
        if binary is None:
            raise SystemExit("polynav bench fleet: --transport mqtt needs mosquitto "
                             "(apt-get install mosquitto)")
        with socket.socket() as probe:
            probe.bind(("127.0.0.1", 0))
            self.port = int(probe.getsockname()[1])
        config = workdir / "mosquitto.conf"
        lines = [f"listener {self.port} 127.0.0.1", "allow_anonymous true",
                 "persistence false", "sys_interval 1", "max_queued_messages 100000",
                 "set_tcp_nodelay true",
                 "log_dest none"]
        if os.geteuid() == 0:
            lines.append("user root")
        config.write_text("\n".join(lines) + "\n", encoding="utf-8")
        self._command = [binary, "-c", str(config)]
        self._cpu_before = 0.0  # [s] of the processes restarted away
        self._start()

    def _start(self) -> None:
        self.process = subprocess.Popen(self._command, stdin=subprocess.DEVNULL,
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline:
            with contextlib.suppress(OSError), socket.create_connection(
                    ("127.0.0.1", self.port), timeout=0.5):
                return
            time.sleep(0.02)
        self.stop()
        raise SystemExit("polynav bench fleet: mosquitto did not start")

    def restart(self) -> None:
        """Kill the broker (no clean goodbye: the clients see their connection drop) and start
        it again on the same port, with nothing kept (``persistence false``)."""
        self._cpu_before += self.cpu() - self._cpu_before
        self.process.kill()
        self.process.wait(timeout=5.0)
        self._start()

    @property
    def url(self) -> str:
        return f"mqtt://127.0.0.1:{self.port}"

    def cpu(self) -> float:
        """CPU seconds the broker has used (over its restarts)."""
        with contextlib.suppress(psutil.Error):
            times = psutil.Process(self.process.pid).cpu_times()
            return self._cpu_before + float(times.user + times.system)
        return self._cpu_before

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=5.0)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait(timeout=5.0)


# -- the workers ---------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class WorkerSpec:
    """One worker's share: robots ``robot<first>`` .. ``robot<first + count - 1>``."""

    index: int
    first: int
    count: int
    total: int
    args: argparse.Namespace
    broker: str
    epoch: dt.datetime


@dataclass(slots=True)
class Sync:
    """What the coordinator and the workers wait on."""

    coordinator_ready: Event
    go: Event
    stop: Event
    start_at: Any  # multiprocessing Value('d'): the common start, time.monotonic()
    ready: Any  # multiprocessing Queue of worker indexes
    results: Any  # multiprocessing Queue of result dicts


def _wait_start(sync: Sync) -> float:
    sync.go.wait()
    t0 = float(sync.start_at.value)
    time.sleep(max(0.0, t0 - time.monotonic()))
    return t0


def _full_worker(spec: WorkerSpec, sync: Sync, starts_of: Starts) -> dict[str, Any]:
    args = spec.args
    world = load_world(args.world)
    sync.coordinator_ready.wait()
    with tempfile.TemporaryDirectory() as tmp, SiteStore.open(
            Path(tmp) / "data", seed_world=world) as store:
        maps = [f.map_name for f in world.floors]
        starts = starts_of(store, maps, spec.total)[spec.first - 1:spec.first - 1 + spec.count]
        vehicles = VehicleConfig(spec.broker, visualization_period=args.visualization_period)
        config = RuntimeConfig(people=args.people, seed=args.seed + spec.first,
                               speed=args.speed, max_lag=3600.0)
        building = Building(store, world, robots=spec.count, starts=starts, config=config,
                            vehicles=vehicles, first_serial=spec.first, fleet_manager=False,
                            epoch=spec.epoch)
        client = MqttTransport(spec.broker, f"polynav/remote{spec.index}")
        remote = RemoteRobots(building.scene, client, local=building.serials,
                              floors={f.map_name: f.name for f in world.floors},
                              epoch=spec.epoch, radius=building.scene.config.robot_radius,
                              max_lead=MAX_LEAD)
        remote.attach(building.runtimes[0])
        client.wait_subscribed(10.0)
        sync.ready.put(spec.index)
        t0 = _wait_start(sync)
        cpu0, wall0, sim0 = time.process_time(), time.monotonic(), building.now()
        building.start()
        end = args.sim_seconds
        while building.now() < end and not sync.stop.is_set():
            time.sleep(0.05)
        building.stop()
        wall, cpu = time.monotonic() - wall0, time.process_time() - cpu0
        sim = building.now() - sim0
        lag = (time.monotonic() - t0) * args.speed - building.now()
        traffic = [a.traffic for a in building.agents]
        bodies = building.scene.bodies
        staleness = remote.bodies.staleness()
        stats = [link.transport.stats() for link in building.links]
        figures = {
            "index": spec.index, "robots": spec.count, "sim": sim, "wall": wall, "cpu": cpu,
            "lag_at_end": lag,
            "contacts": [(c.stamp, c.robot, c.other) for c in building.scene.robot_contacts],
            "other_collisions": sum(1 for b in bodies for c in b.collisions
                                    if c.obstacle != "robot"),
            "traffic_waits": sum(t.waits for t in traffic),
            "traffic_wait_time": sum(t.wait_time for t in traffic),
            "traffic_rejections": sum(t.rejections for t in traffic),
            "lift_waits": [w for r in building.runtimes for w in r.lift_waits],
            "staleness": [staleness.samples, staleness.mean, staleness.p99, staleness.worst],
            "unsent": sum(s.unsent for s in stats),
            "held": remote.held,
        }
        building.close()
        client.close()
    return figures


def lift_stops(world: World) -> dict[str, tuple[tuple[float, float], ...]]:
    """Where each map's lift cars stand (a car's shaft is at one place on every floor)."""
    maps = {f.name: f.map_name for f in world.floors}
    out: dict[str, list[tuple[float, float]]] = {}
    for car in world.lifts:
        for floor in car.floors:
            out.setdefault(maps[floor], []).append((car.shaft.x, car.shaft.y))
    return {k: tuple(v) for k, v in out.items()}


def _kinematic_worker(spec: WorkerSpec, sync: Sync) -> dict[str, Any]:
    args = spec.args
    world = load_world(args.world)
    points = [(f.map_name, p.pose) for f in world.floors for p in f.points
              if p.kind is PointKind.GENERAL]
    config = KinematicConfig(speed=args.kinematic_speed, lift_wait=args.lift_wait,
                             lifts=lift_stops(world),
                             visualization_period=args.visualization_period)
    sync.coordinator_ready.wait()
    mqtt = MqttTransport(spec.broker, f"polynav/kinematic{spec.index}", max_queued=100000)
    shared = SharedClient(mqtt)
    clock = [0.0]
    headers = m.Headers(m.DEFAULT_VERSION, m.DEFAULT_MANUFACTURER, lambda: clock[0], spec.epoch)
    maps = frozenset(f.map_name for f in world.floors)
    vehicles: dict[str, KinematicVehicle] = {}
    for k in range(spec.count):
        serial = f"robot{spec.first + k}"
        map_name, pose = points[(spec.first - 1 + k) % len(points)]
        vehicles[serial] = KinematicVehicle(
            serial, shared, config, start=m.AgvPosition(pose.x, pose.y, pose.theta, map_name,
                                                        True, 1.0),
            maps=maps, headers=headers, phase=k / spec.count)
        shared.publish(m.topic(serial, m.Connection), m.Connection(
            headers.stamp(serial, m.Connection), m.ConnectionState.ONLINE))
    mqtt.wait_subscribed(10.0)
    sync.ready.put(spec.index)
    t0 = _wait_start(sync)
    cpu0, wall0 = time.process_time(), time.monotonic()
    next_all = wall0
    def answer() -> None:
        """Read what arrived and tick the vehicles it was for: an order is answered at once
        (its state is its acknowledgement)."""
        shared.pump()
        for _ in range(3):
            touched = shared.take_touched()
            if not touched:
                break
            for serial in touched:
                vehicles[serial].tick(clock[0])

    while not sync.stop.is_set():
        shared.wait("order", 0.01)
        wall = time.monotonic()
        clock[0] = (wall - t0) * args.speed
        if clock[0] >= args.sim_seconds:
            break
        answer()
        if wall >= next_all:  # every vehicle moves, 10 times a second
            for k, vehicle in enumerate(vehicles.values()):
                vehicle.tick(clock[0])
                if k % ANSWER_EVERY == ANSWER_EVERY - 1:
                    # 500 vehicles' moves and visualizations take ~20 ms: orders that arrive
                    # meanwhile are answered between every few dozen, not after all of them.
                    answer()
            next_all += 0.1
        answer()
    wall, cpu = time.monotonic() - wall0, time.process_time() - cpu0
    for serial in vehicles:
        shared.publish(m.topic(serial, m.Connection), m.Connection(
            headers.stamp(serial, m.Connection), m.ConnectionState.OFFLINE))
    stats = mqtt.stats()
    mqtt.close()
    return {"index": spec.index, "robots": spec.count, "sim": clock[0], "wall": wall, "cpu": cpu,
            "lag_at_end": 0.0, "contacts": [], "other_collisions": 0, "traffic_waits": 0,
            "traffic_wait_time": 0.0, "traffic_rejections": 0, "lift_waits": [],
            "staleness": [0, 0.0, 0.0, 0.0], "unsent": stats.unsent,
            "distance": sum(v.distance for v in vehicles.values())}


def _worker(spec: WorkerSpec, sync: Sync, starts_of: Starts) -> None:
    try:
        if spec.args.agents == "kinematic":
            figures = _kinematic_worker(spec, sync)
        else:
            figures = _full_worker(spec, sync, starts_of)
    except BaseException as exc:  # the coordinator must hear of it rather than wait
        sync.ready.put(-1)
        sync.results.put({"index": spec.index, "error": f"{type(exc).__name__}: {exc}"})
        raise
    sync.results.put(figures)


# -- the coordinator -----------------------------------------------------------------------------


@dataclass(slots=True)
class Sent:
    """An order as the coordinator saw it go out: its first publication (re-sends keep it)."""

    order_id: str
    published: float  # time.monotonic()
    acked: bool = False


@dataclass(slots=True)
class Pending:
    """A mission posted to the fleet manager and not ended yet."""

    target: tuple[str, str]
    queued_at: float  # site time
    dispatched_at: float | None = None  # site time of its first dispatch
    robot: str | None = None
    timed_out: str | None = None  # how its robot stood when it timed out


@dataclass(slots=True)
class Watch:
    """What the coordinator learns from every state it reads (SharedClient's observer) and every
    order the fleet manager publishes (:class:`TimedTransport`)."""

    epoch: dt.datetime
    orders: dict[str, Sent] = field(default_factory=dict)
    latencies: list[float] = field(default_factory=list)
    clocks: dict[str, float] = field(default_factory=dict)
    last_header: dict[str, int] = field(default_factory=dict)
    lost: int = 0
    reordered: int = 0
    states: int = 0

    def published(self, serial: str, order_id: str, wall: float) -> None:
        sent = self.orders.get(serial)
        if sent is None or sent.order_id != order_id:  # not a re-send
            self.orders[serial] = Sent(order_id, wall)

    def observe(self, serial: str, kind: str, item: m.Received, wall: float) -> None:
        if kind != "state" or not isinstance(item, m.State):
            return
        self.states += 1
        last = self.last_header.get(serial)
        if last is not None:
            if item.header.header_id > last + 1:
                self.lost += item.header.header_id - last - 1
            elif item.header.header_id <= last:
                self.reordered += 1
        if last is None or item.header.header_id > last:
            self.last_header[serial] = item.header.header_id
            moment = dt.datetime.fromisoformat(item.header.timestamp.replace("Z", "+00:00"))
            self.clocks[serial] = (moment - self.epoch).total_seconds()
        sent = self.orders.get(serial)
        if sent is None or sent.acked:
            return
        if item.order_id == sent.order_id or any(
                r.reference_key == "orderId" and r.reference_value == sent.order_id
                for e in item.errors for r in e.error_references):
            sent.acked = True
            self.latencies.append(wall - sent.published)


class TimedTransport:
    """The fleet manager's transport in the coordinator: the shared connection, noting the wall
    time just before each order is published (the order latency's start)."""

    def __init__(self, shared: SharedClient, watch: Watch) -> None:
        self.shared = shared
        self.watch = watch

    def publish(self, topic: str, message: m.Message) -> None:
        if isinstance(message, m.Order):
            self.watch.published(message.header.serial_number, message.order_id,
                                 time.monotonic())
        self.shared.publish(topic, message)

    def subscribe(self, topic: str) -> LocalInbox:
        return self.shared.subscribe(topic)


def post_mission(manager: FleetManager, map_name: str, point: str) -> str:
    """Post a mission to ``point`` on ``map_name`` to the fleet manager, as ``POST
    /api/missions`` does; its id. The manager queues it and dispatches it to the best robot."""
    return manager.submit([{"point": point, "map": map_name}]).mission_id


def run_mqtt(args: argparse.Namespace, starts_of: Starts) -> dict[str, Any]:
    """Run the benchmark (see the module docstring); the figures."""
    world = load_world(args.world)
    kinematic = args.agents == "kinematic"
    goals = [(f.map_name, p.name, p.pose) for f in world.floors for p in f.points
             if p.kind is PointKind.GENERAL]
    share = [args.robots // args.processes + (1 if i < args.robots % args.processes else 0)
             for i in range(args.processes)]
    firsts = [1 + sum(share[:i]) for i in range(args.processes)]
    serials = [f"robot{k}" for k in range(1, args.robots + 1)]
    epoch = dt.datetime.now(dt.UTC)
    ctx = mp.get_context("fork")
    sync = Sync(ctx.Event(), ctx.Event(), ctx.Event(), ctx.Value("d", 0.0), ctx.Queue(),
                ctx.Queue())
    with tempfile.TemporaryDirectory() as tmp:
        broker = Broker(Path(tmp))
        workers = []
        try:
            # Forked before any thread of ours starts (MQTT clients run threads).
            for i in range(args.processes):
                spec = WorkerSpec(i, firsts[i], share[i], args.robots, args, broker.url, epoch)
                process = ctx.Process(target=_worker, args=(spec, sync, starts_of),
                                      name=f"fleet-worker-{i}")
                process.start()
                workers.append(process)
            figures = _coordinate(args, sync, broker, serials, goals, epoch, kinematic,
                                  Path(tmp))
        finally:
            sync.stop.set()
            sync.go.set()
            sync.coordinator_ready.set()
            for process in workers:
                process.join(timeout=60.0)
                if process.is_alive():
                    process.kill()
            broker.stop()
    return figures


def _coordinate(args: argparse.Namespace, sync: Sync, broker: Broker, serials: list[str],
                goals: list[tuple[str, str, Pose2D]], epoch: dt.datetime,
                kinematic: bool, tmp: Path) -> dict[str, Any]:
    watch = Watch(epoch)
    mqtt = MqttTransport(broker.url, "polynav/fleet-bench", max_queued=100000)
    # Pumped here only: an outcome the observer saw is then in the master's state at its tick
    # (pumping inside the tick, a robot drained earlier in it kept its state from before its
    # success, and was sent its next order from where it had been: noRouteError).
    shared = SharedClient(mqtt, observer=watch.observe, auto_pump=False)
    world = load_world(args.world)
    with SiteStore.open(tmp / "site", seed_world=world) as store, FleetRecords.open(
            f"sqlite:///{tmp / 'fleet.db'}", name="fleet-bench") as records:
        # The fleet manager `polynav fleet` runs, on the shared connection.
        manager = FleetManager(TimedTransport(shared, watch), records, store,
                               levels={f.map_name: f.level for f in world.floors},
                               config=FleetManagerConfig(events_kept=100_000), epoch=epoch)
        for serial in serials:
            manager.add_robot(serial)
        sys_counts = mqtt.subscribe_raw("$SYS/broker/publish/messages/+")
        mqtt.wait_subscribed(10.0)
        sync.coordinator_ready.set()
        _wait_ready(args, sync)
        t0 = time.monotonic() + 0.2
        sync.start_at.value = t0
        sync.go.set()
        cpu0, broker_cpu0 = time.process_time(), broker.cpu()
        run = _Run(args, manager, serials, goals, kinematic, np.random.default_rng(args.seed))
        counters: list[tuple[float, dict[str, int]]] = []
        next_tick = t0
        time.sleep(max(0.0, t0 - time.monotonic()))
        give_up = t0 + (args.max_wall if args.max_wall is not None
                        else args.sim_seconds / args.speed * 5.0 + 120.0)
        restart_at = args.broker_restart_at
        while True:
            shared.wait("state", 0.005)
            wall = time.monotonic()
            shared.pump()
            now = _site_time(watch, serials, (wall - t0) * args.speed, kinematic)
            if now >= args.sim_seconds - (0.0 if kinematic else STATE_PERIOD) or wall > give_up:
                break
            _read_counters(sys_counts.drain(), counters, wall)
            if restart_at is not None and now >= restart_at:
                restart_at = None
                run.broker_restarts += 1
                broker.restart()
            if wall < next_tick:
                continue
            next_tick = wall + 0.02
            manager.tick(now)
            run.follow(now)
            run.post(now)
        wall_seconds = time.monotonic() - t0
        coordinator_cpu = time.process_time() - cpu0
        broker_cpu = broker.cpu() - broker_cpu0
        sync.stop.set()
        results = []
        for _ in range(args.processes):
            try:
                results.append(sync.results.get(timeout=120.0))
            except Empty:
                break
        mqtt.close()
    errors = [r["error"] for r in results if "error" in r]
    if errors or len(results) < args.processes:
        raise SystemExit(f"polynav bench fleet: workers failed: {errors or 'no results'}")
    return _figures(args, results, watch, run, counters, wall_seconds, coordinator_cpu,
                    broker_cpu)


def _wait_ready(args: argparse.Namespace, sync: Sync) -> None:
    ready = 0
    deadline = time.monotonic() + READY_TIMEOUT
    while ready < args.processes:
        try:
            got = sync.ready.get(timeout=max(0.1, deadline - time.monotonic()))
        except Empty:
            raise SystemExit("polynav bench fleet: the workers did not get ready") from None
        if got < 0:
            raise SystemExit(f"polynav bench fleet: a worker failed: {sync.results.get()}")
        ready += 1


class _Run:
    """The coordinator's missions: posted to the fleet manager, followed through its events."""

    def __init__(self, args: argparse.Namespace, manager: FleetManager, serials: list[str],
                 goals: list[tuple[str, str, Pose2D]], kinematic: bool,
                 rng: np.random.Generator) -> None:
        self.args = args
        self.manager = manager
        self.serials = serials
        self.goals = goals
        self.kinematic = kinematic
        self.rng = rng
        self.pending: dict[str, Pending] = {}
        self.seq = 0
        self.done = self.succeeded = self.deadlocks = self.requeues = 0
        self.broker_restarts = 0
        self.failures: list[str] = []
        self.queue_waits: list[float] = []
        self.rate = (args.mission_rate if args.mission_rate is not None
                     else len(serials) / MISSION_PERIOD)
        self.tokens = float(len(serials))  # every robot's first mission, then the rate
        self.posted = 0
        self.last_post = 0.0

    def follow(self, now: float) -> None:
        """Read the manager's events: dispatches (queue waits) and ends; cancel a mission past
        the timeout."""
        for event in self.manager.events_after(self.seq):
            self.seq = event.seq
            mission_id = event.detail.get("mission")
            pending = self.pending.get(mission_id) if isinstance(mission_id, str) else None
            if pending is None:
                continue
            if event.kind == "mission.dispatched":
                pending.robot = str(event.detail.get("robot"))
                if pending.dispatched_at is None:
                    pending.dispatched_at = event.at
                    self.queue_waits.append(event.at - pending.queued_at)
            elif event.kind == "mission.requeued":
                self.requeues += 1
            elif event.kind in ("mission.done", "mission.failed", "mission.cancelled"):
                assert isinstance(mission_id, str)
                del self.pending[mission_id]
                self.done += 1
                if event.kind == "mission.done":
                    self.succeeded += 1
                    outcome = "succeeded"
                else:
                    why = (f"no end within the mission timeout ({pending.timed_out})"
                           if pending.timed_out else event.detail.get("why", event.kind))
                    outcome = f"failed: {why}"
                    self.failures.append(f"{event.detail.get('robot')} -> {pending.target[0]}/"
                                         f"{pending.target[1]}: {outcome}")
                if self.args.verbose:
                    print(f"t={now:8.1f}s {event.detail.get('robot')} {pending.target}: "
                          f"{outcome}", flush=True)
        for mission_id, pending in list(self.pending.items()):
            if (pending.dispatched_at is not None and not pending.timed_out
                    and now - pending.dispatched_at > self.args.mission_timeout):
                pending.timed_out = _how_it_stands(self.manager, pending.robot)
                self.deadlocks += 1
                self.manager.cancel(mission_id)

    def post(self, now: float) -> None:
        """Keep up to one mission per robot posted: every robot's first at the start, then at
        most ``--mission-rate`` per second of
        site time (default one per robot per minute: the nearest free robot takes each, so a
        fleet kept fully busy only measures how fast the manager can go) and one per 20 robots
        per tick (a starting fleet of 1,000 does not post 1,000 missions in one burst), each to
        a random general point (a full robot's: one no mission is bound for and no robot
        stands within 1 m of)."""
        room = len(self.serials) - len(self.pending)
        self.tokens += (now - self.last_post) * self.rate
        if self.posted >= len(self.serials):
            # Once the first missions are out, at most a second's worth is saved up.
            self.tokens = min(self.tokens, max(1.0, self.rate))
        self.last_post = now
        budget = min(room, max(1, len(self.serials) // DISPATCH_SHARE), int(self.tokens))
        if budget <= 0:
            return
        self.tokens -= budget
        master = self.manager.master
        taken: set[tuple[str, str]] = set() if self.kinematic else (
            {p.target for p in self.pending.values()} | _stood_on(master, self.serials,
                                                                   self.goals))
        maps = None
        if not self.args.cross_floor:  # to the floor of a robot that is free
            busy = {v.serial for v in self.manager.robots() if v.mission is not None}
            maps = [s.agv_position.map_id for serial in self.serials
                    if serial not in busy and (s := master.state(serial)) is not None
                    and s.agv_position is not None and not s.node_states]
        for _ in range(budget):
            if maps is not None and not maps:
                return
            floor = maps.pop(int(self.rng.integers(len(maps)))) if maps is not None else None
            options = [g for g in self.goals if (g[0], g[1]) not in taken
                       and (floor is None or g[0] == floor)]
            if not options:
                continue
            map_name, point, _ = options[int(self.rng.integers(len(options)))]
            if not self.kinematic:
                taken.add((map_name, point))
            mission_id = post_mission(self.manager, map_name, point)
            self.posted += 1
            self.pending[mission_id] = Pending((map_name, point), now)


def _how_it_stands(manager: FleetManager, serial: str | None) -> str:
    """A robot's last state in a few words: why a mission of it timed out."""
    state = manager.master.state(serial) if serial is not None else None
    if state is None:
        return f"{serial}: no state"
    here = state.agv_position
    where = f"at ({here.x:.1f}, {here.y:.1f}) on {here.map_id}" if here else "nowhere"
    errors = ", ".join(f"{e.error_type}: {e.error_description}" for e in state.errors)
    return (f"{serial} {where}, {state.navigation_state}, waiting for "
            f"{state.waiting_for or 'nothing'}, holding {list(state.zones)}, "
            f"{len(state.node_states)} nodes left, errors [{errors}]")


def _stood_on(master: MasterControl, serials: list[str],
              goals: list[tuple[str, str, Pose2D]]) -> set[tuple[str, str]]:
    """The points some robot stands within 1 m of, by its last state (one bound elsewhere
    may not have left yet): no robot is sent there."""
    stood: set[tuple[str, str]] = set()
    for serial in serials:
        state = master.state(serial)
        here = state.agv_position if state is not None else None
        if here is not None:
            stood |= {(g[0], g[1]) for g in goals if g[0] == here.map_id
                      and math.hypot(g[2].x - here.x, g[2].y - here.y) <= 1.0}
    return stood


def _site_time(watch: Watch, serials: list[str], paced: float, kinematic: bool) -> float:
    """The coordinator's site time: the paced clock, held back to the slowest robot's last
    state (full robots state at least every second), so that a worker that falls behind its pace
    does not see its leases expire early. Light vehicles keep the paced clock by construction."""
    if kinematic:
        return paced
    if len(watch.clocks) < len(serials):
        return 0.0
    return min(paced, min(watch.clocks.values()))


def _read_counters(messages: Sequence[Any], counters: list[tuple[float, dict[str, int]]],
                   wall: float) -> None:
    for message in messages:
        name = message.topic.rsplit("/", 1)[-1]
        with contextlib.suppress(ValueError):
            value = int(message.payload)
            if counters and counters[-1][0] > wall - 0.5:
                counters[-1][1][name] = value
            else:
                counters.append((wall, {name: value}))


def _collisions(results: list[dict[str, Any]]) -> int:
    """Robot pairs' contacts counted once across the processes (both may see one touch), plus
    every contact with a wall or a person."""
    by_pair: dict[frozenset[str], list[float]] = {}
    for r in results:
        for stamp, robot, other in r["contacts"]:
            by_pair.setdefault(frozenset((robot, other)), []).append(float(stamp))
    pairs = 0
    for stamps in by_pair.values():
        stamps.sort()
        last = -math.inf
        for stamp in stamps:
            if stamp - last > CONTACT_WINDOW:
                pairs += 1
            last = stamp
    return pairs + sum(int(r["other_collisions"]) for r in results)


def _figures(args: argparse.Namespace, results: list[dict[str, Any]], watch: Watch, run: _Run,
             counters: list[tuple[float, dict[str, int]]], wall: float, coordinator_cpu: float,
             broker_cpu: float) -> dict[str, Any]:
    done, succeeded = run.done, run.succeeded
    queue_waits = np.asarray(run.queue_waits)
    sim = min(float(r["sim"]) for r in results)
    latencies = np.asarray(watch.latencies) * 1000.0
    lift_waits = [w for r in results for w in r["lift_waits"]]
    waits = sum(int(r["traffic_waits"]) for r in results)
    rates = {}
    for name in ("received", "sent"):
        seen = [(t, c[name]) for t, c in counters if name in c]
        if len(seen) >= 2 and seen[-1][0] > seen[0][0]:
            # A restarted broker counts from 0 again: its first count is all new.
            total = sum(b - a if b >= a else b for (_, a), (_, b) in
                        itertools.pairwise(seen))
            rates[name] = round(total / (seen[-1][0] - seen[0][0]), 1)
    stale = [r["staleness"] for r in results if r["staleness"][0]]
    worst = max((s[3] for s in stale), default=0.0)
    p99 = max((s[2] for s in stale), default=0.0)
    worker_cpu = sum(float(r["cpu"]) for r in results)
    kinematic = args.agents == "kinematic"
    return {
        "transport": "mqtt",
        "agents": "kinematic (light mode)" if kinematic else "full",
        "world": args.world, "robots": args.robots, "processes": args.processes,
        "people": args.people, "cross_floor": args.cross_floor, "seed": args.seed,
        "speed": args.speed, "sim_seconds": round(sim, 1), "wall_seconds": round(wall, 1),
        "missions": done, "succeeded": succeeded,
        "success_rate": round(succeeded / done, 4) if done else 0.0,
        "missions_per_hour": round(succeeded / (sim / 3600.0), 1) if sim > 0 else 0.0,
        "failed": run.failures, "deadlocks": run.deadlocks,
        "dispatch": "fleet manager (polynav fleet's FleetManager, SQLite records)",
        "mission_rate_per_s": round(run.rate, 2),
        "missions_unfinished": len(run.pending), "mission_requeues": run.requeues,
        "queue_wait_p50_s": round(float(np.percentile(queue_waits, 50)), 2)
        if len(queue_waits) else None,
        "queue_wait_p99_s": round(float(np.percentile(queue_waits, 99)), 2)
        if len(queue_waits) else None,
        "broker_restarts": run.broker_restarts,
        "collisions": _collisions(results),
        "lease_waits": waits,
        "mean_lease_wait_s": round(sum(float(r["traffic_wait_time"]) for r in results) / waits,
                                   2) if waits else 0.0,
        "lease_rejections": sum(int(r["traffic_rejections"]) for r in results),
        "lift_rides": len(lift_waits),
        "mean_lift_wait_s": round(sum(lift_waits) / len(lift_waits), 2) if lift_waits else 0.0,
        "orders_acknowledged": len(latencies),
        "order_latency_p50_ms": round(float(np.percentile(latencies, 50)), 1)
        if len(latencies) else None,
        "order_latency_p99_ms": round(float(np.percentile(latencies, 99)), 1)
        if len(latencies) else None,
        "order_latency_max_ms": round(float(latencies.max()), 1) if len(latencies) else None,
        "broker_messages_per_s": rates,
        "broker_cpu_per_s": round(broker_cpu / wall, 3) if wall > 0 else 0.0,
        "states_read": watch.states, "lost_state_messages": watch.lost,
        "reordered_state_messages": watch.reordered,
        "unsent_messages": sum(int(r["unsent"]) for r in results),
        "real_time_factor": round(min(float(r["sim"]) / float(r["wall"]) for r in results), 2),
        "max_lag_at_end_s": round(max(float(r["lag_at_end"]) for r in results), 2),
        "held_for_slower_s": round(max(float(r.get("held", 0.0)) for r in results), 1),
        "cpu_per_robot": round(worker_cpu / sim / args.robots, 4) if sim > 0 else 0.0,
        "coordinator_cpu_per_s": round(coordinator_cpu / wall, 3) if wall > 0 else 0.0,
        "visualization_period_s": args.visualization_period,
        "remote_pose_samples": sum(int(s[0]) for s in stale),
        "remote_pose_delay_p99_s": round(p99, 3),
        "remote_pose_delay_max_s": round(worst, 3),
        "remote_pose_staleness_max_s": round(args.visualization_period + worst, 3)
        if not kinematic else None,
        "shared_connection": kinematic,
        "budget_order_latency_p99_ms": BUDGET_LATENCY_P99 * 1000.0,
    }


def report(figures: dict[str, Any]) -> list[str]:
    """The figures as lines for a person."""
    f = figures
    lines = [
        f"MQTT fleet, {f['agents']} agents: {f['robots']} robots in {f['processes']} processes "
        f"at {f['speed']}x, {f['sim_seconds']:.0f} s simulated in {f['wall_seconds']:.0f} s: "
        f"{f['missions']} missions, {f['succeeded']} succeeded "
        f"({f['success_rate'] * 100:.1f} %), {f['missions_per_hour']:.1f} per hour",
        f"collisions {f['collisions']} (robot pairs once across processes), deadlocks "
        f"{f['deadlocks']}, lease waits {f['lease_waits']} (mean {f['mean_lease_wait_s']} s, "
        f"{f['lease_rejections']} rejections), lift rides {f['lift_rides']} (mean wait "
        f"{f['mean_lift_wait_s']} s)",
        f"dispatch by the {f['dispatch']}, missions posted at most {f['mission_rate_per_s']}"
        f"/s: queue wait p50 {f['queue_wait_p50_s']} s, p99 "
        f"{f['queue_wait_p99_s']} s (site time, posted -> dispatched); requeued "
        f"{f['mission_requeues']}, unfinished at the end {f['missions_unfinished']}, broker "
        f"restarts {f['broker_restarts']}",
        f"order latency (publish -> first state acknowledging it) p50 "
        f"{f['order_latency_p50_ms']} ms, p99 {f['order_latency_p99_ms']} ms, max "
        f"{f['order_latency_max_ms']} ms over {f['orders_acknowledged']} orders",
        f"broker messages/s {f['broker_messages_per_s']} (Mosquitto $SYS), broker CPU "
        f"{f['broker_cpu_per_s'] * 100:.1f} % of a core; states read {f['states_read']}, lost "
        f"(headerId gaps) {f['lost_state_messages']}, reordered "
        f"{f['reordered_state_messages']}, unsent {f['unsent_messages']}",
        f"real-time factor {f['real_time_factor']:.2f}x (lag at end {f['max_lag_at_end_s']} s), "
        f"CPU per robot {f['cpu_per_robot'] * 100:.2f} % of a core at 1x, coordinator "
        f"{f['coordinator_cpu_per_s'] * 100:.1f} % of a core",
    ]
    if f["shared_connection"]:
        lines.append("light mode: kinematic vehicles (no sensors, no localization, no zones; "
                     "straight lines, a lift a fixed wait), one MQTT connection per process: "
                     "no per-vehicle last will")
    else:
        lines.append(
            f"remote robots: poses every {f['visualization_period_s']} s, arriving up to "
            f"{f['remote_pose_delay_max_s']} s (p99 {f['remote_pose_delay_p99_s']} s) of site "
            f"time late: drawn at most {f['remote_pose_staleness_max_s']} s stale, moved on "
            f"along their velocity; workers kept within {MAX_LEAD} s of each other (waited "
            f"up to {f['held_for_slower_s']} s of wall time for a slower one)")
    lines += [f"  FAILED {failure}" for failure in f["failed"]]
    return lines


def dumps(figures: dict[str, Any]) -> str:
    return orjson.dumps(figures).decode()
