"""The robot runtime: one robot's clock, backend, site, services, events and status, together.

:class:`RobotRuntime` is the single owner of a robot's live state (DESIGN §1). Adapters (the
native API, vendor dialects) call its command methods from their own threads; the tick loop is
the only writer of robot state, so commands are applied *between* ticks: while the loop thread
runs (:meth:`RobotRuntime.start`) a command is queued and the caller waits for the loop to run
it at the start of the next physics step; without the thread (tests, :meth:`advance`) it runs at
once under the runtime's lock. Reads (:meth:`status`, :meth:`settings`) return prebuilt frozen
values and never wait.

Each physics step (the simulator's rate, 50 Hz) the loop applies queued commands, stops a
teleop command that has timed out (the dead-man), and, when a control period is due
(``control_rate``), ticks the navigation stack (localization, costmap, navigator), applies a
teleop or local-move velocity when no goal runs, publishes events for whatever changed
(e-stop, charging, localization, low battery; navigation events come from the navigator as they
happen) and refreshes the status snapshot; then it steps the simulator.

Modes follow the vendors' documented transitions: ``FREE`` after power-on; starting or stopping
navigation passes through ``BUSY`` (map and localization being loaded or unloaded) to
``NAVIGATING`` or back to ``FREE``. ``MAPPING`` belongs to the mapping service (a later issue):
the runtime refuses navigation commands while in it.

Attempt ids are the runtime's, unique for its lifetime: every time the navigation stack is
rebuilt (a new map, new settings) its navigator counts from 1 again, so the runtime adds an
offset.

The backend is the simulator (:meth:`RobotRuntime.simulated`) or a real robot over rosbridge
(:meth:`RobotRuntime.bridged`); what placing the robot means on each is
:mod:`~polynav.runtime.placement`.

The runtime coordinates; the parts do one job each: :mod:`~polynav.runtime.loop` (the loop
thread, its pacing and the command queue), :mod:`~polynav.runtime.navigation_events` (attempt
ids and navigator events as runtime events), :mod:`~polynav.runtime.watchers` (e-stop, charge,
low battery and localization changes), :mod:`~polynav.runtime.direct_motion` (teleop and local
moves), :mod:`~polynav.runtime.placement` (floors, and placing the simulated robot),
:mod:`~polynav.runtime.step_hooks` (timers and step listeners) and
:mod:`~polynav.runtime.relocalization` (finding a lost robot). The class itself is written in
parts by subject: :mod:`~polynav.runtime.goal_commands` (goals, patrols, pause, cancel),
:mod:`~polynav.runtime.motion_commands` (teleop, e-stop, local moves),
:mod:`~polynav.runtime.control_tick` (one physics step's work and the checks that publish
events), :mod:`~polynav.runtime.settings_commands` (reading and changing settings) and
:mod:`~polynav.runtime.loop_commands` (running the loop, calls between ticks, timers), over
the shared :mod:`~polynav.runtime.internals`; :mod:`~polynav.runtime.config` holds its modes
and settings.
"""

from __future__ import annotations

import datetime as dt
import logging
import threading
from pathlib import Path

from polynav.automation.runner import AutomationRunner
from polynav.clock import Clock
from polynav.errors import Conflict
from polynav.geometry import Pose2D, Twist
from polynav.maps.keepout import Keepout
from polynav.maps.map import Map
from polynav.nav.stack import NavigationStack, StackConfig, stack_config_for
from polynav.robot.interface import Backend, Robot
from polynav.robot.profile import DEFAULT_PROFILE, RobotProfile, load_profile
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.devices import simulated_devices
from polynav.robot.sim.devices.axis import SimAxis
from polynav.robot.sim.jack_link import JackLink
from polynav.robot.sim.simulation import Simulation
from polynav.runtime import events
from polynav.runtime.auto_charge import AutoCharge
from polynav.runtime.automation_tasks import AutomationTasks
from polynav.runtime.cart_commands import CartCommands
from polynav.runtime.config import Mode, RuntimeConfig, SiteData
from polynav.runtime.control_tick import ControlTick
from polynav.runtime.device import Device
from polynav.runtime.device_commands import Peripherals
from polynav.runtime.direct_motion import DirectMotion
from polynav.runtime.door_commands import DoorCommands
from polynav.runtime.door_passage import DoorPassage
from polynav.runtime.event_bus import EventBus
from polynav.runtime.exploration import Exploration
from polynav.runtime.goal_commands import GoalCommands
from polynav.runtime.http_callbacks import HttpCallbacks
from polynav.runtime.lift_commands import LiftCommands
from polynav.runtime.lift_sessions import LocalLiftSessions
from polynav.runtime.loop import CommandLoop
from polynav.runtime.loop_commands import LoopCommands
from polynav.runtime.map_exchange import MapExchange
from polynav.runtime.mapless_commands import MaplessCommands
from polynav.runtime.mapping_commands import MappingCommands
from polynav.runtime.mapping_jobs import MappingJobs
from polynav.runtime.mapping_session import MappingSession
from polynav.runtime.motion_commands import MotionCommands
from polynav.runtime.navigation_commands import NavigationCommands
from polynav.runtime.navigation_events import AttemptBook
from polynav.runtime.no_entry import NoEntrySigns
from polynav.runtime.patrols import Patrols
from polynav.runtime.placement import Placement, ReportedPlacement, SimulatedPlacement
from polynav.runtime.relocalization import LostRecovery
from polynav.runtime.settings import RobotSettings
from polynav.runtime.settings_commands import SettingsCommands
from polynav.runtime.site_queries import SiteQueries
from polynav.runtime.status import StatusSnapshot
from polynav.runtime.status_report import StatusReport
from polynav.runtime.step_hooks import StepHooks
from polynav.runtime.task_commands import TaskCommands
from polynav.runtime.warm_up import warm_up
from polynav.runtime.watchers import BatteryWatcher, EStopWatcher, LocalizationWatcher
from polynav.worlds.world import World

log = logging.getLogger(__name__)


class RobotRuntime(
    SettingsCommands, NavigationCommands, GoalCommands, LiftCommands, DoorCommands, MotionCommands,
    MappingCommands, MaplessCommands, StatusReport, ControlTick, LoopCommands,
):
    """One robot: backend, navigation stack, commands, events and status on one clock.

    Build it with :meth:`simulated` or :meth:`bridged`. Args are the parts: ``store`` (site
    data), ``backend`` (the simulator or a real robot's backend; its clock is the runtime's
    clock), ``config``.
    """

    def __init__(
        self,
        store: SiteData,
        backend: Backend,
        *,
        config: RuntimeConfig | None = None,
        stack_config: StackConfig | None = None,
        loop: CommandLoop | None = None,
        profile: RobotProfile | None = None,
        name: str = "robot",
    ) -> None:
        self.config = config or RuntimeConfig()
        self.store = store
        self.bus = EventBus()
        self.tasks = TaskCommands(self)  # first: every event published is noted for tasks
        self._backend = backend
        self._sim = backend if isinstance(backend, Simulation) else None
        self._robot = backend.robot
        self._clock = backend.clock
        self._place: Placement = (
            SimulatedPlacement(self._sim) if self._sim is not None
            else ReportedPlacement(name, _first_floor(store)))
        self.profile = profile or load_profile(DEFAULT_PROFILE)
        self._base_stack_config = stack_config_for(self.profile, stack_config)
        self._settings = RobotSettings.from_stored(store.settings(), self.profile)
        self._settings_dirty = False
        self._settings_lock = threading.Lock()
        self._mode = Mode.FREE
        self._stack: NavigationStack | None = None
        self._map_name: str | None = None
        self._grid: Map | None = None
        self._keepouts: tuple[Keepout, ...] = ()
        self._mapless = False
        self._motion = DirectMotion(self._robot, self.config.teleop_timeout)
        self._software_estop = False
        self._estop = EStopWatcher(self._robot.estop_pressed())
        self._battery = BatteryWatcher(
            self._robot.read_battery(), self._settings.low_battery_percent
        )
        self._localization = LocalizationWatcher()
        self._recovery = LostRecovery(self._restart_localization)
        self._mapping: MappingSession | None = None
        self._exploration: Exploration | None = None
        self._mapping_jobs = MappingJobs()  # saves of the map being built (mapping_commands)
        # Attempt bookkeeping (the runtime's ids, see the module docstring).
        self._attempts = AttemptBook()
        # Goals on other maps (lift_commands): the running and the last route, the router.
        self._route = None
        self._route_last = None
        self._router = None
        self._path_costs = None
        self._lift_sessions = None
        self._lift_hold = None
        self.lift_waits = []
        # Doors on the way (door_passage): a lone robot lends itself doors from its own book;
        # in a building the fleet's agent puts in its leases.
        self.doors_rule = DoorPassage(self, lambda: self._place.doors,
                                      LocalLiftSessions(self._place.name, kind="door"))
        # Timing.
        self._control_period = 1.0 / self.config.control_rate
        self._next_control = self._clock.now()
        # The loop thread and its command queue; robots sharing one simulated world share one
        # loop that ticks each of them and steps the world once (polynav.house.building).
        self._loop = loop if loop is not None else CommandLoop(
            step=self._step,
            now=self.now,
            physics_period=backend.physics_period,
            # A real robot's backend waits for its own time in step(): the loop does not pace.
            speed=self.config.speed if self._sim is not None else 0.0,
            max_lag=self.config.max_lag,
            after_command=self._refresh,
            on_failure=lambda: self._robot.drive(Twist()),
        )
        # Timers the services set and listeners of every step (servers' sensor streams).
        self._hooks = StepHooks()
        # The current or last patrol (a task over several goals), if any.
        self._patrols = Patrols(self.tasks.engine, self._publish, self.now)
        self._auto_charge = AutoCharge(self)
        # False while the (simulated) robot is powered off: commands are refused.
        self.powered = True
        self.device = Device(self)
        self._no_entry = NoEntrySigns(self._robot, self._publish, lambda: self._keepouts)
        devices = simulated_devices(self._clock.now(), self._robot.read_scan,
                                    seed=self.config.seed)
        self.peripherals = Peripherals(self, devices, getattr(store, "data_dir", None))
        jack = devices.jacking
        if self._sim is not None and isinstance(jack, SimAxis):  # stepped before the carts
            self.add_step_listener(JackLink(self._sim, jack, self.profile.payload).follow)
        self.carts = CartCommands(self)  # carts and cabins: dock, carry, leave
        self.queries = SiteQueries(self)
        data_dir = getattr(store, "data_dir", None)
        self.automations = AutomationTasks(self, AutomationRunner(
            self.tasks, None if data_dir is None else Path(data_dir) / "automations",
            enabled=self.config.automations, limits=self.config.automation_limits))
        # A task's HTTP callbacks, sent from worker threads (never on the loop).
        self.callbacks = HttpCallbacks(self.config.task_callback_hosts)
        # Maps sent to and fetched from dispatch servers, on worker threads too.
        self.map_exchange = MapExchange(dict(self.config.dispatch_servers), self.callbacks)
        # The calendar schedules run on (docs/decisions.md, "Task schedules"): the runtime is
        # the layer that may read the wall clock, once, when no epoch is given.
        self.calendar_epoch = self.config.calendar_epoch or dt.datetime.now().replace(
            microsecond=0)
        self._snapshot = self._build_snapshot(self._clock.now())
        self.tasks.load()

    @classmethod
    def simulated(
        cls,
        store: SiteData,
        world: World,
        *,
        config: RuntimeConfig | None = None,
        sim_config: SimConfig | None = None,
        stack_config: StackConfig | None = None,
        profile: RobotProfile | None = None,
    ) -> RobotRuntime:
        """A runtime on the simulator, the robot standing at the world's start pose, FREE.

        Args:
            store: the site (maps, points, keepouts, settings).
            world: the simulated ground truth; its floors' maps should be the site's maps.
            config: runtime settings (seed, speed, rates).
            sim_config: the simulated robot's other settings (physics, battery, people);
                defaults to :class:`SimConfig`.
            stack_config: the navigation stack's base configuration; the profile and then the
                settings override it.
            profile: the robot (body, limits, sensors); defaults to the world's ``robot:``
                entry, else the demo robot. The simulator and the stack are both built from it.
        """
        config = config or RuntimeConfig()
        warm_up()
        profile = profile or world.robot or load_profile(DEFAULT_PROFILE)
        sim = Simulation(
            world, config=profile.sim_config(sim_config), seed=config.seed, people=config.people
        )
        return cls(store, sim, config=config, stack_config=stack_config, profile=profile)

    @classmethod
    def bridged(
        cls,
        store: SiteData,
        backend: Backend,
        *,
        config: RuntimeConfig | None = None,
        stack_config: StackConfig | None = None,
        profile: RobotProfile | None = None,
        name: str = "robot",
    ) -> RobotRuntime:
        """A runtime on a real robot's backend (:mod:`polynav.robot.rosbridge`), FREE.

        The robot's clock is the runtime's; there is no ground truth, so navigation starts from
        the point or pose the operator gives (or the map's initial point), and the robot's
        floor is the one last named (:class:`~polynav.runtime.placement.ReportedPlacement`).
        """
        warm_up()
        return cls(store, backend, config=config, stack_config=stack_config,
                   profile=profile or load_profile(DEFAULT_PROFILE), name=name)

    # -- reads (any thread, never wait) --------------------------------------------------------

    @property
    def clock(self) -> Clock:
        """The runtime's clock (simulated time on the simulator); adapters pace streams on it."""
        return self._clock

    def now(self) -> float:
        """The runtime's clock [s] (simulated time on the simulator)."""
        return self._clock.now()

    def calendar_now(self) -> dt.datetime:
        """The robot's calendar date-time now: ``calendar_epoch`` + the clock (local, naive)."""
        return self.calendar_epoch + dt.timedelta(seconds=self._clock.now())

    def calendar_iso(self) -> str:
        """:meth:`calendar_now` as ISO text to the second, as the store keeps it."""
        return self.calendar_now().isoformat(timespec="seconds")

    @property
    def robot(self) -> Robot:
        """The robot backend (sensors, battery, e-stop); read it, never drive it."""
        return self._robot

    @property
    def simulation(self) -> Simulation:
        """The simulator backend (ground truth, for tests and the demo).

        Raises:
            Conflict: the robot is a real one (:attr:`is_simulated` is false).
        """
        if self._sim is None:
            raise Conflict("this robot is not simulated: there is no simulator to ask")
        return self._sim

    @property
    def physics_period(self) -> float:
        """The backend's step [s of the runtime's clock]: odometry comes at this period."""
        return self._backend.physics_period

    @property
    def is_simulated(self) -> bool:
        """Whether the backend is the simulator (ground truth, wifi and lifts of its world)."""
        return self._sim is not None

    @property
    def mode(self) -> Mode:
        return self._mode

    @property
    def map_name(self) -> str | None:
        """The map navigation runs on, ``None`` unless NAVIGATING."""
        return self._map_name

    def status(self) -> StatusSnapshot:
        """The snapshot of the last refresh (O(1), no lock)."""
        return self._snapshot

    @property
    def navigation_stack(self) -> NavigationStack | None:
        """The navigation stack while NAVIGATING (costmap, navigator, estimate), else ``None``.

        For read-only queries from the loop thread or inside :meth:`run_between_ticks`; its
        state changes every tick.
        """
        return self._stack

    def publish(self, event: events.RuntimeEvent) -> None:
        """Publish ``event`` on the runtime's bus (for the runtime's own services)."""
        self._publish(event)

    # -- navigation internals ----------------------------------------------------------------

    def _set_mode(self, mode: Mode) -> None:
        old = self._mode
        if old is mode:
            return
        self._mode = mode
        log.info("mode %s -> %s", old.value, mode.value)
        self._publish(events.ModeChanged(self.now(), old.value, mode.value))

    def _refresh(self) -> None:
        """Rebuild the snapshot now, so a status read right after a command shows its effect."""
        self._snapshot = self._build_snapshot(self.now())

    def refresh_status(self) -> None:
        """Rebuild the status snapshot now (a loop shared by several robots, after a command)."""
        self._refresh()

    def _floor_now(self) -> str | None:
        return self._place.floor

    def _refuse_if_shutting_down(self, what: str) -> None:
        self.device.power.refuse_if_pending(what)

    def _status_pose(self) -> Pose2D:
        return self._snapshot.pose

    def _publish(self, event: events.RuntimeEvent) -> None:
        self.tasks.note(event)
        self.bus.publish(event)


def _first_floor(store: SiteData) -> str:
    """The site's lowest floor: where a real robot is taken to be until told otherwise."""
    floors = store.floors()
    name = getattr(floors[0], "name", None) if floors else None
    return name if isinstance(name, str) else "1"
