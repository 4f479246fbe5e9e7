"""A building of several simulated robots: one world, one clock, one loop, one fleet.

``polynav run --robots N`` and ``polynav bench fleet`` build one :class:`Building`: a
:class:`~polynav.robot.sim.scene.Scene` of the site's world with N robot bodies in it, one
:class:`~polynav.runtime.robot_runtime.RobotRuntime` per robot (each still the single owner of its
robot's state, DESIGN §9), the fleet's :class:`~polynav.fleet.manager.FleetManager` (its
master control with the lease book, missions dispatched from its records: SQLite in memory
unless given a database), and one :class:`~polynav.fleet.agent.RobotAgent` per robot, joined by
an in-process transport or an MQTT broker. With ``fleet_manager=False`` (``polynav run
--robots N --broker URL --no-fleet-manager``) the building holds only the vehicles, for a
``polynav fleet`` in another process.

One :class:`~polynav.runtime.loop.CommandLoop` drives them all. Each physics step it ticks every
runtime (timers, control), then, every control period, the master control and the agents, then
steps the world once: the robots move on one clock and see one another. A command for any robot
(its native API, a dialect) runs between steps, like a lone robot's.

Robots start on the site's free start points (:func:`start_points`), one robot per point.
"""

from __future__ import annotations

import datetime as dt
import logging
import time
from collections.abc import Callable, Sequence

from polynav.api.fleet_listing import FleetEntry, OrderState
from polynav.errors import InvalidRequest
from polynav.fleet.agent import RobotAgent
from polynav.fleet.interface import Transport
from polynav.fleet.manager import FleetManager
from polynav.fleet.master_control import MasterControl, Stop
from polynav.fleet.messages import DEFAULT_MANUFACTURER, DEFAULT_VERSION, State
from polynav.fleet.mqtt_transport import MqttTransport
from polynav.fleet.records import FleetRecords, Mission
from polynav.fleet.traffic import TrafficConfig
from polynav.fleet.transport import InProcessTransport
from polynav.fleet.vehicle import VehicleConfig, VehicleLink
from polynav.fleet.zones import ZoneConfig, ZoneMap, find_zones
from polynav.geometry import Pose2D, Twist
from polynav.leases.book import LeaseBookConfig
from polynav.nav.stack import StackConfig
from polynav.robot.profile import DEFAULT_PROFILE, RobotProfile, load_profile
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.scene import Scene
from polynav.robot.sim.simulation import Simulation
from polynav.runtime.config import RuntimeConfig, SiteData
from polynav.runtime.loop import CommandLoop
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.runtime.warm_up import warm_up
from polynav.site import Point, PointKind
from polynav.worlds.world import World

log = logging.getLogger(__name__)

_EPS = 1e-9
STANDBY_PREFIX = "standby"
"""Points whose name starts with this are standby points: robots may start there."""


def start_points(store: SiteData, world: World, *, robot_radius: float) -> list[Point]:
    """The site's free start points: each floor's initial point, its chargers, then its standby
    points, floor by floor (lowest level first); a point too close to one already chosen for
    two robots to stand there is left out."""
    maps = {f.map_name: f for f in world.floors}
    chosen: list[Point] = []
    order = {PointKind.INITIAL: 0, PointKind.CHARGER: 1}
    candidates = [p for p in store.points() if p.map_name in maps and (
        p.kind in order or p.name.startswith(STANDBY_PREFIX))]
    candidates.sort(key=lambda p: (maps[p.map_name].level, order.get(p.kind, 2), p.name))
    for p in candidates:
        if all(q.map_name != p.map_name or q.pose.distance_to(p.pose) > 2.5 * robot_radius
               for q in chosen):
            chosen.append(p)
    return chosen


class Building:
    """N simulated robots on one site (see the module docstring).

    Args:
        store: the site (maps, points, settings), shared by the robots.
        world: the simulated ground truth.
        robots: how many robots; at least 1 and at most the free start points.
        config: runtime settings for every robot (robot ``i`` is seeded ``seed + i``).
        sim_config: the simulated robots.
        stack_config: their navigation stacks' base configuration.
        starts: where the robots start; the site's free start points if None.
        traffic: the traffic rule's distances and timings.
        leases: the lease book's timings.
        profile: the robots (body, limits, sensors), all alike; defaults to the world's
            ``robot:`` entry, else the demo robot.
        vehicles: VDA 5050 over MQTT: each robot a client of this broker (connection,
            factsheet, its own will) and the master control another; None for the in-process
            transport. Only the transport changes.
        fleet_manager: run the fleet manager here (False: vehicles only, needs ``vehicles``;
            a fleet manager elsewhere on the broker runs the fleet).
        records: the fleet manager's records database URL; SQLite in memory if None.
        first_serial: robot ``i`` is ``robot<first_serial + i>``: the buildings of several
            processes sharing one site number their robots apart.
        epoch: the UTC moment site time 0 stands for; processes sharing one site pass one, so
            their headers' timestamps agree; by default, when the building is made.

    Raises:
        InvalidRequest: fewer than 1 robot, more robots than start points, a start point on no
            floor of the world.
        BrokerUnreachable: ``vehicles`` names a broker that cannot be reached.
    """

    def __init__(
        self,
        store: SiteData,
        world: World,
        *,
        robots: int,
        config: RuntimeConfig | None = None,
        sim_config: SimConfig | None = None,
        stack_config: StackConfig | None = None,
        starts: Sequence[Point] | None = None,
        traffic: TrafficConfig | None = None,
        leases: LeaseBookConfig | None = None,
        profile: RobotProfile | None = None,
        vehicles: VehicleConfig | None = None,
        fleet_manager: bool = True,
        records: str | None = None,
        first_serial: int = 1,
        epoch: dt.datetime | None = None,
    ) -> None:
        config = config or RuntimeConfig()
        profile = profile or world.robot or load_profile(DEFAULT_PROFILE)
        sim_config = profile.sim_config(sim_config)
        if robots < 1:
            raise InvalidRequest("robots", f"must be at least 1, got {robots}")
        if not fleet_manager and vehicles is None:
            raise InvalidRequest("fleet_manager", "a building without its fleet manager needs "
                                                  "a broker for one elsewhere")
        points = list(starts) if starts is not None else start_points(
            store, world, robot_radius=sim_config.robot_radius)
        if robots > len(points):
            names = ", ".join(f"{p.map_name}/{p.name}" for p in points) or "none"
            raise InvalidRequest(
                "robots", f"{robots} robots but only {len(points)} free start points ({names}); "
                          f"add charger or '{STANDBY_PREFIX}...' points to the site")
        floors = {f.map_name: f.name for f in world.floors}
        for p in points[:robots]:
            if p.map_name not in floors:
                raise InvalidRequest("starts", f"map {p.map_name!r} is on no floor of the world")
        warm_up()
        self.store = store
        self.world = world
        self.config = config
        self.scene = Scene(world, sim_config, people=config.people)
        self._loop = CommandLoop(
            step=self._step,
            now=self.scene.clock.now,
            physics_period=sim_config.physics_period,
            speed=config.speed,
            max_lag=config.max_lag,
            after_command=self._refresh,
            on_failure=self._brake,
        )
        # One calendar for every header in the building: site time 0 is now.
        if epoch is None:
            epoch = dt.datetime.now(dt.UTC) - dt.timedelta(seconds=self.scene.clock.now())
        self.links: list[VehicleLink] = []
        self._mqtt: list[MqttTransport] = []
        version = vehicles.version if vehicles is not None else DEFAULT_VERSION
        manufacturer = vehicles.manufacturer if vehicles is not None else DEFAULT_MANUFACTURER
        self.transport: Transport
        self.fleet: FleetManager | None = None
        self.records: FleetRecords | None = None
        if vehicles is None:
            self.transport = InProcessTransport()
        elif fleet_manager:
            master_client = MqttTransport(vehicles.broker, f"{manufacturer}/master",
                                          connect_timeout=vehicles.connect_timeout)
            self._mqtt.append(master_client)
            self.transport = master_client
        if fleet_manager:
            self.records = FleetRecords.open(records or "sqlite://", name="building")
            levels = {f.map_name: f.level for f in world.floors}
            self.fleet = FleetManager(self.transport, self.records, store, levels=levels,
                                      leases=leases, version=version,
                                      manufacturer=manufacturer, epoch=epoch)
        zone_config = ZoneConfig(robot_radius=sim_config.robot_radius)
        self.zones: dict[str, ZoneMap] = {
            name: find_zones(name, store.load_map(name), zone_config) for name in floors
        }
        self.runtimes: list[RobotRuntime] = []
        self.agents: list[RobotAgent] = []
        self.starts = tuple(points[:robots])
        self.ports: dict[str, dict[str, int]] = {}
        for i, point in enumerate(self.starts):
            serial = f"robot{i + first_serial}"
            sim = Simulation(world, config=sim_config, seed=config.seed + i,
                             floor=floors[point.map_name], pose=point.pose, scene=self.scene,
                             name=serial)
            runtime = RobotRuntime(store, sim, config=config, stack_config=stack_config,
                                   loop=self._loop, profile=profile)
            self.runtimes.append(runtime)
            if self.fleet is not None:
                self.fleet.add_robot(serial)
            transport: Transport
            on_factsheet_request: Callable[[], None] | None
            if vehicles is None:
                transport, on_factsheet_request = self.transport, None
            else:
                link = VehicleLink(serial, profile, vehicles, clock=self.scene.clock.now,
                                   epoch=epoch, order_period=1.0 / config.control_rate)
                self.links.append(link)
                transport, on_factsheet_request = link.transport, link.publish_factsheet
            self.agents.append(RobotAgent(
                serial, runtime, transport, self.zones, traffic=traffic, version=version,
                manufacturer=manufacturer, epoch=epoch,
                visualization_period=vehicles.visualization_period if vehicles else None,
                on_factsheet_request=on_factsheet_request))
        self._fleet_period = 1.0 / config.control_rate
        self._next_fleet = self.scene.clock.now()
        for runtime, point in zip(self.runtimes, self.starts, strict=True):
            runtime.start_navigation(point.map_name, pose=point.pose)
        # Each robot says where it is before the first order: an order starts where it stands.
        self._prime(vehicles.connect_timeout if vehicles is not None else 0.0)
        log.info("building of %d robots on world %r", robots, world.name)

    # -- reads ---------------------------------------------------------------------------------

    @property
    def master(self) -> MasterControl:
        """The fleet's master control (orders, leases).

        Raises:
            InvalidRequest: the building runs without its fleet manager.
        """
        if self.fleet is None:
            raise InvalidRequest("fleet_manager", "this building's fleet manager runs "
                                                  "elsewhere")
        return self.fleet.master

    @property
    def mqtt_clients(self) -> tuple[MqttTransport, ...]:
        """Every MQTT client of the building (the master's, each robot's), none in process."""
        return (*self._mqtt, *(link.transport for link in self.links))

    @property
    def serials(self) -> tuple[str, ...]:
        return tuple(agent.serial_number for agent in self.agents)

    def now(self) -> float:
        return self.scene.clock.now()

    def agent(self, serial: str) -> RobotAgent:
        """The agent of robot ``serial``.

        Raises:
            InvalidRequest: no such robot.
        """
        for agent in self.agents:
            if agent.serial_number == serial:
                return agent
        raise InvalidRequest("robot", f"no robot {serial!r} in the building")

    def entries(self) -> list[FleetEntry]:
        """Every robot as the fleet knows it (its last state message) and where it listens."""
        out = []
        for agent in self.agents:
            serial = agent.serial_number
            state = (self.fleet.master.state(serial) if self.fleet is not None
                     else agent.state())
            status = agent.runtime.status()  # mode is not in VDA's state; read the snapshot
            position = state.agv_position if state is not None else None
            errors = tuple(e.error_description for e in state.errors) if state else ()
            stamp = (self.fleet.master.state_time(serial) if self.fleet is not None
                     else self.now())
            out.append(FleetEntry(
                robot_id=serial,
                ports=dict(self.ports.get(serial, {})),
                floor=state.floor if state is not None else status.floor,
                map_name=position.map_id if position is not None else status.map,
                pose=(Pose2D(position.x, position.y, position.theta) if position is not None
                      else status.pose),
                mode=status.mode,
                navigation_state=state.navigation_state if state else status.navigation_state,
                order_id=state.order_id if state is not None else "",
                order_state=_order_state(state),
                waiting_for=state.waiting_for if state is not None else None,
                zones=state.zones if state is not None else (),
                battery_percent=(state.battery_state.battery_charge if state is not None
                                 else status.battery_percent),
                stamp=stamp,
                errors=errors,
            ))
        return out

    # -- commands ------------------------------------------------------------------------------

    def send(self, serial: str, point: str, map_name: str) -> str:
        """Send robot ``serial`` an order to ``point`` on ``map_name``; returns the order id.

        Raises:
            InvalidRequest: no such robot. NotFound: no such point.
        """
        self.agent(serial)
        pose = self.store.point(map_name, point).pose
        return self._loop.call(
            lambda: self.master.send_order(serial, [Stop(point, map_name, pose)]))

    def submit(self, stops: list[tuple[str, str]], *, mission_id: str | None = None) -> str:
        """Queue a mission through ``stops`` (``(point, map_name)`` in order) with the fleet
        manager, which gives it to the best robot; returns its id.

        Raises:
            InvalidRequest: no stops, or no fleet manager here. NotFound: no such point.
        """
        fleet = self._fleet()
        return fleet.submit([{"point": p, "map": m} for p, m in stops],
                            mission_id=mission_id).mission_id

    def mission(self, mission_id: str) -> Mission:
        """A mission as the fleet manager's records hold it.

        Raises:
            NotFound: no such mission. InvalidRequest: no fleet manager here.
        """
        return self._fleet().mission(mission_id)

    def _fleet(self) -> FleetManager:
        if self.fleet is None:
            raise InvalidRequest("fleet_manager", "this building's fleet manager runs "
                                                  "elsewhere")
        return self.fleet

    def outcome(self, serial: str, order_id: str) -> str | None:
        """How robot ``serial``'s order ended (``"succeeded"``, ``"failed: <why>"``), None
        while it runs or before the robot has it."""
        return self.agent(serial).outcome_of(order_id)

    def advance(self, seconds: float) -> None:
        """Run every robot ``seconds`` of simulated time, as fast as the machine goes."""
        self._loop.advance_until(lambda: False, seconds)

    def advance_until(self, done: Callable[[], bool], timeout: float) -> bool:
        """Run until ``done()`` holds or ``timeout`` simulated seconds pass; whether it held."""
        return self._loop.advance_until(done, timeout)

    def start(self) -> None:
        """Run the loop on a thread, paced at ``config.speed`` × wall time."""
        self._loop.start()

    def stop(self) -> None:
        """Stop the loop thread (idempotent)."""
        self._loop.stop()

    def close(self) -> None:
        """Stop the loop; over MQTT, each robot says OFFLINE and every client disconnects."""
        self.stop()
        for link in self.links:
            link.close()
        for client in self._mqtt:
            client.close()
        if self.records is not None:
            self.records.close()

    def _prime(self, wait: float) -> None:
        """Publish every robot's state and read them on the master's side, waiting up to
        ``wait`` [s of wall time] for a broker to carry them (and the subscriptions first)."""
        deadline = time.monotonic() + wait
        for client in [*self._mqtt, *(link.transport for link in self.links)]:
            client.wait_subscribed(max(0.0, deadline - time.monotonic()))
        now = self.scene.clock.now()
        for agent in self.agents:
            agent.publish_state(now)
        fleet = self.fleet
        if fleet is None:
            return
        while True:
            fleet.tick(now)
            if all(fleet.master.state(s) is not None for s in self.serials):
                return
            if time.monotonic() >= deadline:
                log.warning("not every robot's first state reached the master")
                return
            time.sleep(0.01)

    # -- the loop ------------------------------------------------------------------------------

    def _step(self) -> None:
        now = self.now()
        for runtime in self.runtimes:
            runtime.tick()
        if now >= self._next_fleet - _EPS:
            if self.fleet is not None:
                self.fleet.tick(now)
            for agent in self.agents:
                agent.tick(now)
            self._next_fleet += self._fleet_period
            if self._next_fleet <= now:
                self._next_fleet = now + self._fleet_period
        self.scene.step()
        for runtime in self.runtimes:
            runtime.stepped()

    def _refresh(self) -> None:
        for runtime in self.runtimes:
            runtime.refresh_status()

    def _brake(self) -> None:
        for runtime in self.runtimes:
            runtime.robot.drive(Twist())


def _order_state(state: State | None) -> OrderState:
    """``none``, ``running``, ``succeeded`` or ``failed`` from a robot's last state."""
    if state is None or not state.order_id:
        return "none"
    if any(e.error_type == "orderFailed" for e in state.errors):
        return "failed"
    return "running" if state.node_states else "succeeded"
