"""Shared fixtures (where the project's data lives) and the order tests run in.

The maps, scenarios and endpoint lists the tests read are shipped in the repository's ``data/``
(``data/README.md``: sources, licences, checksums), so a clone with nothing beside it runs every
test.
"""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
DATA = REPO / "data"


@pytest.fixture(scope="session")
def data_dir() -> Path:
    return DATA


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Slow scenario tests first: with ``-n 2`` each worker starts on a long one and the short
    ones fill in round them, instead of two minutes-long tests ending the run one after the
    other. The order within each group stays the collection order (the same on every worker)."""
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)
