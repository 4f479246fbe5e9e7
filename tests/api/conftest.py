"""Fixtures: the API over real HTTP around a fake runtime on a real, seeded site store."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.api.fakes import FakeRuntime
from tests.api.server import native_client


@pytest.fixture
def fake_runtime(tmp_path: Path, world: World) -> Iterator[FakeRuntime]:
    store = SiteStore.open(tmp_path / "data", seed_world=world)
    yield FakeRuntime(store)
    store.close()


@pytest.fixture
def client(fake_runtime: FakeRuntime) -> Iterator[httpx.Client]:
    with native_client(fake_runtime) as http:
        yield http
