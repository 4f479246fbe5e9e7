from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.store import SiteStore
from polynav.worlds import load_world
from polynav.worlds.world import World


@pytest.fixture(scope="session")
def demo_world() -> World:
    return load_world("demo")


@pytest.fixture
def demo_store(tmp_path: Path, demo_world: World) -> Iterator[SiteStore]:
    store = SiteStore.open(tmp_path / "data", seed_world=demo_world)
    yield store
    store.close()


@pytest.fixture
def empty_store(tmp_path: Path) -> Iterator[SiteStore]:
    store = SiteStore.open(tmp_path / "data")
    yield store
    store.close()
