"""Shared fixtures: where the project's data lives.

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
