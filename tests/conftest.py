"""Shared fixtures (where the project's data lives, the demo site in a fresh store) and the
order tests run in.

The maps, scenarios and endpoint lists the tests read are shipped in the repository's ``data/``
(``data/README.md``: sources, licences, checksums), so a clone with nothing beside it runs every
test.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from polynav.worlds.world import World

REPO = Path(__file__).resolve().parent.parent
DATA = REPO / "data"


@pytest.fixture(scope="session")
def data_dir() -> Path:
    return DATA


@pytest.fixture(scope="session")
def world() -> World:
    """The demo site (a module may define its own ``world``)."""
    return load_world("demo")


@pytest.fixture
def store(world: World, tmp_path: Path) -> Iterator[SiteStore]:
    """A site store of its own for each test, seeded with ``world``'s maps and points."""
    with SiteStore.open(tmp_path / "data", seed_world=world) as opened:
        yield opened


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Slow scenario tests first: with ``-n 2`` each worker starts on a long one and the short
    ones fill in round them, instead of two minutes-long tests ending the run one after the
    other. The order within each group stays the collection order (the same on every worker)."""
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)
