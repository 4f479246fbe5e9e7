"""A "no entry" sign over the real socket (01210): a sign stands in office 1's door, facing the
corridor, and the robot (a profile with a sign camera) is sent from the corridor to a desk in
the office. It spots the sign, the notice goes out, and the robot never passes it: the way in
is closed, and it plans round it, through the office's other door."""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from polynav.geometry import Pose2D
from polynav.robot.profile import SignCamera, load_profile
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.site import Point
from polynav.store.site_store import SiteStore
from polynav.worlds.world import NoEntrySign, World
from tests.protocols.yunji.conftest import Client, serving

SIGN = NoEntrySign(11.6, 12.9, -math.pi / 2)  # in office 1's door, facing the corridor
CORRIDOR = Pose2D(14.8, 12.0, math.pi)


def _world_with_sign(world: World) -> World:
    floors = tuple(dataclasses.replace(f, signs=(SIGN,)) if f.name == "floor1" else f
                   for f in world.floors)
    return dataclasses.replace(world, floors=floors, start_pose=CORRIDOR)


def _codes_until_end(client: Client) -> list[dict[str, Any]]:
    notes = []
    while not notes or notes[-1]["code"] not in ("01002", "01003"):
        notes.append(client.push("notification"))
    return notes


def _run(world: World, store: SiteStore, camera: SignCamera | None
         ) -> tuple[list[dict[str, Any]], float, RobotRuntime]:
    """Send the robot to the desk; the notices of the move and its closest pass by the sign."""
    store.add_point(Point("desk_office_1", "floor1", Pose2D(11.6, 16.5, math.pi / 2)))
    profile = dataclasses.replace(load_profile(), sign_camera=camera)
    runtime = RobotRuntime.simulated(store, _world_with_sign(world),
                                     config=RuntimeConfig(people=False), profile=profile)
    with serving(runtime) as h:
        client = h.client()
        runtime.set_initial_pose(CORRIDOR)
        runtime.advance(0.5)
        assert client.request("/api/move?marker=desk_office_1")["status"] == "OK"
        closest = math.inf
        for _ in range(240):
            runtime.advance(0.5)
            pose = runtime.simulation.true_pose
            closest = min(closest, math.hypot(pose.x - SIGN.x, pose.y - SIGN.y))
            if runtime.status().navigation_state not in ("running", "paused"):
                break
        return _codes_until_end(client), closest, runtime


def test_a_no_entry_sign_in_the_way_sends_01210_and_is_not_passed(
        world: World, store: SiteStore) -> None:
    notes, closest, runtime = _run(world, store, SignCamera(range=4.0, fov=1.2))
    codes = [n["code"] for n in notes]
    assert codes.count("01210") == 1, codes  # once per sign
    note = next(n for n in notes if n["code"] == "01210")
    assert (note["level"], note["description"], note["data"]) == (
        "warning", "Detect no entry, zero velocity control.", {})
    assert closest > 0.5, closest  # it never went through the door the sign closes
    assert codes[-1] == "01002", codes  # round by the other door
    desk = runtime.store.point("floor1", "desk_office_1").pose
    assert runtime.simulation.true_pose.distance_to(desk) < 0.1
    assert runtime.simulation.collisions == []


def test_a_robot_without_a_sign_camera_drives_through(world: World, store: SiteStore) -> None:
    """The control: the same sign, a robot with no camera: no notice, and in it goes."""
    notes, closest, _ = _run(world, store, None)
    codes = [n["code"] for n in notes]
    assert "01210" not in codes and codes[-1] == "01002", codes
    assert closest < 0.5


COVERED: dict[str, str] = {
    "notify 10 01210": "test_a_no_entry_sign_in_the_way_sends_01210_and_is_not_passed",
}
