"""Every entry of ros1-nav-iface.endpoints.json is served by polynav's rosbridge graph and has
a test over the wire (each test module's ``COVERED``: entry path -> test name)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import tests.protocols.rosbridge as package
from polynav.protocols.ros_graph import Graph
from polynav.protocols.rosbridge.androidmsg import add_androidmsg
from polynav.protocols.rosbridge.robot_topics import add_robot_topics
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.helpers.coverage import covered_entries

SPEC = Path(__file__).resolve().parents[3] / "data" / "spec" / "ros1-nav-iface.endpoints.json"
ENTRIES = json.loads(SPEC.read_text(encoding="utf-8"))
COVERED = covered_entries(package)


def test_the_entry_list_is_the_specs() -> None:
    assert len(ENTRIES) == 36
    assert len({e["path"] for e in ENTRIES}) == 36


def test_every_entry_has_a_test_over_the_wire() -> None:
    missing = sorted({e["path"] for e in ENTRIES} - set(COVERED))
    assert missing == []
    assert sorted(set(COVERED) - {e["path"] for e in ENTRIES}) == []


@pytest.fixture
def graph(world: World, store: SiteStore) -> Graph:
    runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))
    g = Graph()
    add_robot_topics(g, runtime)
    add_androidmsg(g, runtime)
    return g


def test_every_entry_is_served(graph: Graph) -> None:
    for entry in ENTRIES:
        path, method = entry["path"], entry["method"]
        if method == "topic-sub":
            assert graph.topic(path) is not None, path
        elif method == "topic-pub":
            assert graph.subscription(path) is not None, path
        else:
            assert method == "service" and graph.service(path) is not None, path
