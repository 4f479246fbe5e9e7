"""Trapped in unknown area (01201) over the real socket: a floor mapped only in part (its walls
known, its floor grey beyond a few metres of the robot and of the goal), navigated with
unknown-as-obstacle on. The lidar clears the grey floor it sees, within its reach and line of
sight; every way to the kitchen still runs through grey cells, so no plan is found, and the cause
is told apart from an obstacle: 01201 with 01203, then the move fails as unreachable."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest

from polynav.geometry import Pose2D
from polynav.maps.costmap import CostmapConfig
from polynav.maps.map import FREE, UNKNOWN, Map
from polynav.nav.stack import StackConfig
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.protocols.yunji.conftest import Client, Harness, serving

KNOWN_AROUND = 3.0  # [m] of known floor round the robot's start and round the goal


def _mapped_in_part(grid: Map, around: list[Pose2D]) -> Map:
    """``grid`` with its free cells grey (unknown) except within KNOWN_AROUND of ``around``."""
    info = grid.info
    iy, ix = np.mgrid[0:info.height, 0:info.width]
    x = info.origin.x + (ix + 0.5) * info.resolution
    y = info.origin.y + (iy + 0.5) * info.resolution
    known = np.zeros(grid.data.shape, dtype=bool)
    for pose in around:
        known |= np.hypot(x - pose.x, y - pose.y) <= KNOWN_AROUND
    data = grid.data.copy()
    data[(data == FREE) & ~known] = UNKNOWN
    return Map(info, data)


@pytest.fixture
def harness(world: World, store: SiteStore) -> Iterator[Harness]:
    kitchen = store.point("floor1", "kitchen").pose
    store.save_map("floor1", _mapped_in_part(store.load_map("floor1"),
                                             [world.start_pose, kitchen]))
    stack = StackConfig(costmap=CostmapConfig(track_unknown=True))
    runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False),
                                     stack_config=stack)
    with serving(runtime) as h:
        yield h


def test_a_robot_walled_in_by_unknown_space_sends_01201(harness: Harness) -> None:
    client: Client = harness.client()
    reply = client.request("/api/move?marker=kitchen")
    assert reply["status"] == "OK", reply
    for _ in range(120):
        harness.runtime.advance(0.5)
        if harness.runtime.status().navigation_state != "running":
            break
    assert harness.runtime.status().navigation_state == "failed"
    codes = []
    while not codes or codes[-1] != "01003":
        codes.append(client.push("notification")["code"])
    assert codes[:3] == ["01001", "01201", "01203"], codes
    assert "01202" not in codes  # nothing is in the way: the map is what is missing
    assert codes[-2:] == ["01007", "01003"]


def test_the_same_robot_with_unknown_space_as_free_goes(world: World, store: SiteStore) -> None:
    """The control: the same map taken with unknown as free (the default) plans through the
    grey floor, sends no 01201, and the robot gets under way."""
    kitchen = store.point("floor1", "kitchen").pose
    store.save_map("floor1", _mapped_in_part(store.load_map("floor1"),
                                             [world.start_pose, kitchen]))
    runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))
    with serving(runtime) as h:
        client = h.client()
        assert client.request("/api/move?marker=kitchen")["status"] == "OK"
        runtime.advance(5.0)
        assert runtime.status().navigation_state == "running"
        assert runtime.simulation.true_pose.distance_to(world.start_pose) > 0.5
        client.request("/api/move/cancel")
        codes = []
        while not codes or codes[-1] != "01004":
            codes.append(client.push("notification")["code"])
        assert "01201" not in codes


COVERED: dict[str, str] = {
    "notify 10 01201": "test_a_robot_walled_in_by_unknown_space_sends_01201",
}
