"""The simulated door: timing, holders, its leaf in the ground truth (lidar and body), the
safety beam that keeps it from closing on a robot, and a controller that stops answering."""

from __future__ import annotations

import math

import pytest

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D, Twist
from polynav.robot.door import OPERATOR
from polynav.robot.lift import DoorState
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.scene import Scene
from polynav.robot.sim.simulation import Simulation
from polynav.worlds import load_world
from polynav.worlds.world import World

DOOR = "fire_door_west"  # floor 2's corridor, x = 15.3, y 10.9..13.0


@pytest.fixture(scope="module")
def demo() -> World:
    return load_world("demo")


def _steps(scene: Scene, seconds: float) -> None:
    for _ in range(round(seconds / scene.config.physics_period)):
        scene.step()


def _front_range(body: Simulation) -> float:
    scan = body.scan
    assert scan is not None
    k = int(abs(scan.angles).argmin())
    return float(scan.ranges[k])


def test_door_opens_in_its_time_for_its_holders_and_closes_when_none_is_left(
        demo: World) -> None:
    scene = Scene(demo, SimConfig(), people=False)
    door = scene.doors[DOOR]
    assert door.state().state is DoorState.CLOSED and door.blocking
    door.open("robot1")
    door.open(OPERATOR)
    _steps(scene, 1.0)
    assert door.state().state is DoorState.OPENING and door.blocking
    _steps(scene, 1.1)
    status = door.state()
    assert status.state is DoorState.OPEN and not door.blocking
    assert status.holders == ("operator", "robot1")
    door.close("robot1")
    _steps(scene, 3.0)
    assert door.state().state is DoorState.OPEN  # the operator still holds it
    door.close(OPERATOR)
    assert door.state().state is DoorState.CLOSING
    _steps(scene, 2.1)
    assert door.state().state is DoorState.CLOSED and door.blocking
    with pytest.raises(InvalidRequest):
        door.open("")


def test_the_closed_leaf_is_seen_by_the_lidar_and_stops_the_body(demo: World) -> None:
    scene = Scene(demo, SimConfig(), people=False)
    body = Simulation(demo, scene=scene, floor="floor2", pose=Pose2D(14.0, 12.0, 0.0), seed=1)
    _steps(scene, 0.3)
    # The leaf is 1.3 m ahead of the robot's centre (the lidar sits near it).
    assert _front_range(body) == pytest.approx(1.25, abs=0.2)
    body.drive(Twist(0.5, 0.0))
    _steps(scene, 4.0)
    assert body.collisions, "the body drove through a closed door"
    assert body.true_pose.x < 15.3 - 0.2
    # Opened, the lidar sees down the corridor and the leaf's cells are walls no more.
    scene.doors[DOOR].open(OPERATOR)
    _steps(scene, 2.5)
    assert _front_range(body) > 5.0
    floor = scene.floors["floor2"]
    ix, iy = floor.info.world_to_cell(15.3, 12.0)
    assert not floor.occupied[iy, ix]


def test_the_door_does_not_close_on_a_robot_in_its_passage(demo: World) -> None:
    scene = Scene(demo, SimConfig(), people=False)
    door = scene.doors[DOOR]
    door.open("robot")
    _steps(scene, 2.5)
    # A closed leaf is a wall: no robot can be put there; an open door's passage is free.
    body = Simulation(demo, scene=scene, floor="floor2", pose=Pose2D(15.3, 12.0, 0.0), seed=1)
    door.close("robot")
    _steps(scene, 5.0)
    assert door.state().state is DoorState.CLOSING and not door.blocking
    body.teleport("floor2", Pose2D(17.0, 12.0, math.pi))
    _steps(scene, 2.5)
    assert door.state().state is DoorState.CLOSED and door.blocking


def test_a_controller_that_does_not_answer_keeps_its_state_and_ignores_requests(
        demo: World) -> None:
    scene = Scene(demo, SimConfig(), people=False)
    door = scene.doors[DOOR]
    door.set_answering(False)
    door.open("robot1")
    _steps(scene, 5.0)
    status = door.state()
    assert (status.state, status.holders, status.answering) == (DoorState.CLOSED, (), False)
    door.set_answering(True)
    door.open("robot1")
    _steps(scene, 2.1)
    assert door.state().state is DoorState.OPEN
