"""Advance a simulation and a navigation stack together on simulated time.

Physics steps at the simulator's rate; the stack is ticked at its control rate on the same
simulated clock. Nothing here sleeps: how fast simulated time passes is only a question of how
fast the machine computes, which is what makes whole missions take seconds in tests.
"""

from __future__ import annotations

from collections.abc import Callable

from polynav.geometry import Pose2D
from polynav.nav.mapless import MaplessConfig, MaplessStack
from polynav.nav.navigator import EventSink
from polynav.nav.stack import NavigationStack, StackConfig, stack_config_for
from polynav.robot.profile import RobotProfile
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.simulation import Simulation
from polynav.worlds.world import World


class SimDriver:
    """Runs ``stack`` on ``sim`` in lock-step.

    Args:
        sim: the simulated robot.
        stack: its navigation stack.
        mapless: whether the stack's frame is the odometry frame (navigation without a map)
            rather than the map, which the simulator's world shares.
    """

    def __init__(self, sim: Simulation, stack: NavigationStack, *, mapless: bool = False) -> None:
        self.sim = sim
        self.stack = stack
        self.mapless = mapless
        self._period = 1.0 / stack.config.control_rate
        self._next_control = sim.clock.now()

    @property
    def now(self) -> float:
        return self.sim.clock.now()

    def to_odometry(self, pose: Pose2D) -> Pose2D:
        """A world pose in the odometry frame, which starts at (0, 0, 0) where the simulated
        base was created (as a real base's does where it is switched on)."""
        return self.sim.world_to_odometry(pose)

    def to_stack_frame(self, pose: Pose2D) -> Pose2D:
        """A world pose as the stack takes goals: unchanged on a map (its frame is the
        world's), in the odometry frame without one. For tests and benchmarks whose goals are
        drawn in world coordinates."""
        return self.to_odometry(pose) if self.mapless else pose

    def step(self) -> None:
        """One physics step, and a control tick when one is due."""
        if self.now >= self._next_control - 1e-9:
            self.stack.tick(self.now)
            self._next_control += self._period
        self.sim.step()

    def run(self, seconds: float) -> None:
        """Advance ``seconds`` of simulated time."""
        end = self.now + seconds
        while self.now < end - 1e-9:
            self.step()

    def run_until(self, done: Callable[[], bool], timeout: float) -> bool:
        """Advance until ``done()`` holds or ``timeout`` simulated seconds pass.

        Returns:
            Whether ``done()`` held before the timeout.
        """
        end = self.now + timeout
        while not done():
            if self.now >= end:
                return False
            self.step()
        return True


def simulate(
    world: World,
    *,
    seed: int = 0,
    floor: str | None = None,
    pose: Pose2D | None = None,
    initial_guess: Pose2D | None = None,
    people: bool = True,
    sim_config: SimConfig | None = None,
    stack_config: StackConfig | None = None,
    on_event: EventSink | None = None,
    profile: RobotProfile | None = None,
) -> SimDriver:
    """A simulated robot in ``world`` with a navigation stack, localized and ready for goals.

    Args:
        world: the ground truth; the stack navigates on the same floor map.
        seed: seeds every noise source of the simulator.
        floor: floor name; defaults to the world's start floor.
        pose: true start pose; defaults to the world's start pose.
        initial_guess: the pose given to localization (as an operator would set it); defaults to
            the true pose, and may be off by up to about 1 m / 30°.
        people: whether the floor's walkers walk.
        profile: the robot; the simulator (over ``sim_config``) and the stack (over
            ``stack_config``) are both built from it. Defaults to the world's ``robot:`` entry;
            with neither, the two configs are used as given.
    """
    profile = profile or world.robot
    if profile is not None:
        sim_config = profile.sim_config(sim_config)
        stack_config = stack_config_for(profile, stack_config)
    sim = Simulation(
        world, config=sim_config or SimConfig(), seed=seed, floor=floor, pose=pose, people=people
    )
    stack = NavigationStack(
        sim.robot, world.floor(sim.floor).map, config=stack_config, on_event=on_event
    )
    stack.initialize(initial_guess or sim.true_pose, sim.clock.now())
    return SimDriver(sim, stack)


def simulate_mapless(
    world: World,
    *,
    seed: int = 0,
    floor: str | None = None,
    pose: Pose2D | None = None,
    people: bool = True,
    sim_config: SimConfig | None = None,
    stack_config: StackConfig | None = None,
    mapless: MaplessConfig | None = None,
    on_event: EventSink | None = None,
    profile: RobotProfile | None = None,
) -> SimDriver:
    """A simulated robot in ``world`` that navigates with no map (:mod:`polynav.nav.mapless`).

    The world is the simulator's ground truth only: the stack never sees its map. Goals are
    poses in the odometry frame, which starts at (0, 0, 0) where the robot stands at first
    (``Pose2D(10, 0, 0)`` is 10 m ahead of it); a goal drawn in world coordinates goes through
    :meth:`SimDriver.to_odometry` first.

    Args:
        as :func:`simulate`; ``mapless`` sets the rolling window and the localizer.
    """
    profile = profile or world.robot
    if profile is not None:
        sim_config = profile.sim_config(sim_config)
        stack_config = stack_config_for(profile, stack_config)
    sim = Simulation(
        world, config=sim_config or SimConfig(), seed=seed, floor=floor, pose=pose, people=people
    )
    stack = MaplessStack(sim.robot, config=stack_config, mapless=mapless, on_event=on_event)
    return SimDriver(sim, stack, mapless=True)
