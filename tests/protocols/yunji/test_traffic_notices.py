"""The fleet's traffic rule over the real socket: two robots of one building, each with its own
Yunji server, meet at office 1's door (one narrow passage, a traffic zone). The one that must
wait hears the passage is busy (01200), that it waits at the narrow area (01033) and, once the
other is through, that it goes on (01034); the one that goes first hears none of them."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import pytest

from polynav.geometry import Pose2D
from polynav.house.building import Building
from polynav.protocols.yunji import YunjiConfig, serve
from polynav.runtime.config import RuntimeConfig
from polynav.site import Point, PointKind
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.helpers.loop_thread import LoopThread
from tests.protocols.yunji.conftest import Client

TRAFFIC = ("01200", "01033", "01034")


@pytest.fixture
def building(world: World, store: SiteStore) -> Iterator[Building]:
    # As tests/scenario/test_fleet.py: robot 1 in office 1 leaves for the lobby while robot 2,
    # in the corridor outside, goes in through the same one-robot door.
    inside = Point("start_in_office_1", "floor1", Pose2D(11.6, 15.5, -math.pi / 2),
                   PointKind.GENERAL)
    corridor = Point("start_in_corridor", "floor1", Pose2D(14.8, 12.0, math.pi),
                     PointKind.GENERAL)
    store.add_point(Point("desk_office_1", "floor1", Pose2D(11.6, 16.5, math.pi / 2)))
    b = Building(store, world, robots=2, starts=[inside, corridor],
                 config=RuntimeConfig(people=False))
    yield b
    b.close()


def _codes_until_end(client: Client) -> list[str]:
    """The notification codes of one move, 01001 to its end (01002/01003)."""
    codes: list[str] = []
    while True:
        packet: dict[str, Any] = client.push("notification")
        codes.append(packet["code"])
        if packet["code"] in ("01002", "01003"):
            return codes


def test_the_robot_that_waits_for_the_narrow_door_hears_01200_01033_01034(
        building: Building) -> None:
    loop = LoopThread()
    servers = [loop.run(serve(runtime, YunjiConfig(port=0))) for runtime in building.runtimes]
    clients = [Client(server.port) for server in servers]
    try:
        building.advance(0.5)
        for client, marker in zip(clients, ("lobby", "desk_office_1"), strict=True):
            reply = client.request(f"/api/move?marker={marker}")
            assert reply["status"] == "OK", reply

        def ended() -> bool:
            return all(r.status().navigation_state in ("succeeded", "failed")
                       for r in building.runtimes)

        assert building.advance_until(ended, timeout=240.0)
        assert [r.status().navigation_state for r in building.runtimes] == ["succeeded"] * 2
        heard = [_codes_until_end(client) for client in clients]
        waiters = [i for i, codes in enumerate(heard) if "01033" in codes]
        assert len(waiters) == 1, heard
        waiter, first = heard[waiters[0]], heard[1 - waiters[0]]
        assert not set(TRAFFIC) & set(first), first
        told = [c for c in waiter if c in TRAFFIC]
        # Busy first (the fleet queued it), then one wait (moving up in line is the same
        # wait), ended when it got the door; then the move ends.
        assert told == ["01200", "01033", "01034"], waiter
        assert waiter[0] == "01001" and waiter[-1] == "01002"
        waits = [building.agent(s).traffic.waits for s in building.serials]
        assert waits[waiters[0]] >= 1
    finally:
        for client in clients:
            client.close()
        for server in servers:
            loop.run(server.close())
        loop.close()


_TEST = "test_the_robot_that_waits_for_the_narrow_door_hears_01200_01033_01034"
COVERED: dict[str, str] = {f"notify 10 {code}": _TEST for code in TRAFFIC}
