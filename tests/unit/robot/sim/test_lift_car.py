"""The simulated lift car: travel time, door timing, sessions, capacity, out of service, and the
scene carrying a robot that stands in the car."""

from __future__ import annotations

import pytest

from polynav.clock import ManualClock
from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.robot.lift import (
    DoorRequest,
    DoorState,
    LiftBusy,
    LiftMode,
    LiftOutOfService,
    LiftRequest,
    MotionState,
)
from polynav.robot.sim.config import SimConfig
from polynav.robot.sim.lift_car import SimLiftCar
from polynav.robot.sim.scene import Scene
from polynav.robot.sim.simulation import Simulation
from polynav.worlds import load_world
from polynav.worlds.world import LiftCar, LiftShaft

DT = 0.02


def _car(riders: int = 0) -> tuple[SimLiftCar, ManualClock]:
    clock = ManualClock()
    spec = LiftCar("A", LiftShaft(0.0, 0.0, 2.0, 2.0), ("f1", "f2", "f3"), "out", "in",
                   speed=1.0, floor_height=3.5, door_time=2.0, capacity=2)
    car = SimLiftCar(spec, {"f1": 1, "f2": 2, "f3": 3}, lambda floor: riders, clock.now)
    return car, clock


def _run(car: SimLiftCar, clock: ManualClock, seconds: float) -> None:
    for _ in range(round(seconds / DT)):
        car.step(DT)
        clock.set(round(clock.now() + DT, 9))


def test_call_opens_the_doors_after_door_time_and_holds_them() -> None:
    car, clock = _car()
    car.request(LiftRequest("r1", "f1", DoorRequest.OPEN))
    _run(car, clock, 1.0)
    assert car.state().door is DoorState.OPENING
    _run(car, clock, 1.02)
    state = car.state()
    assert state.door is DoorState.OPEN and state.ready_at("f1") and state.session_id == "r1"
    _run(car, clock, 60.0)
    assert car.state().door is DoorState.OPEN  # held while the session asks for it


def test_ride_of_two_floors_closes_travels_seven_seconds_and_opens() -> None:
    car, clock = _car()
    car.request(LiftRequest("r1", "f1"))
    _run(car, clock, 2.1)
    car.request(LiftRequest("r1", "f3"))
    assert car.expected_arrival("f3") == pytest.approx(2.0 + 7.0 + 2.0)
    _run(car, clock, 2.1)  # doors closed
    assert car.state().door is DoorState.CLOSED
    _run(car, clock, 3.0)
    assert car.state().motion is MotionState.UP
    _run(car, clock, 4.1)
    assert car.state().current_floor == "f3" and car.state().motion is MotionState.STOPPED
    _run(car, clock, 2.1)
    assert car.state().ready_at("f3")


def test_second_session_is_refused_until_the_first_ends() -> None:
    car, clock = _car()
    car.request(LiftRequest("r1", "f2"))
    with pytest.raises(LiftBusy):
        car.request(LiftRequest("r2", "f1"))
    car.request(LiftRequest("r1", end_session=True))
    car.request(LiftRequest("r2", "f1"))
    assert car.state().session_id == "r2"


def test_unserved_floor_and_out_of_service_are_refused() -> None:
    car, _ = _car()
    with pytest.raises(InvalidRequest, match="does not serve floor 'f9'"):
        car.request(LiftRequest("r1", "f9"))
    car.set_mode(LiftMode.OUT_OF_SERVICE)
    with pytest.raises(LiftOutOfService):
        car.request(LiftRequest("r1", "f1"))
    assert car.state().mode is LiftMode.OUT_OF_SERVICE and car.state().session_id == ""


def test_out_of_service_mid_trip_finishes_the_trip_and_opens() -> None:
    car, clock = _car()
    car.request(LiftRequest("r1", "f3"))
    _run(car, clock, 2.0)
    car.set_mode(LiftMode.OUT_OF_SERVICE)
    _run(car, clock, 7.1)  # 7 s of travel, 2 s of doors
    state = car.state()
    assert state.current_floor == "f3" and state.door is DoorState.OPEN


def test_people_fill_the_car() -> None:
    car, _ = _car(riders=1)
    assert not car.state().full
    car.board_people(1)
    assert car.state().full and car.state().riders == 2


def test_scene_carries_a_robot_standing_in_the_car_to_the_new_floor() -> None:
    world = load_world("demo")
    scene = Scene(world, SimConfig(), people=False)
    inside = world.floor("floor1").point("lift_1_inside").pose
    body = Simulation(world, scene=scene, floor="floor1", pose=inside, seed=1)
    other = Simulation(world, scene=scene, floor="floor1", pose=Pose2D(8.0, 8.5, 0.0), seed=2)
    car = scene.lifts["lift_1"]
    car.request(LiftRequest("robot1", "floor3"))
    for _ in range(round(20.0 / scene.config.physics_period)):
        scene.step()
    assert body.floor == "floor3" and body.true_pose.distance_to(inside) < 1e-6
    assert other.floor == "floor1"
    assert car.state().ready_at("floor3") and car.state().riders == 1
