"""Polling a live process (a server in another process, a broker) until a check holds."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import pytest


def wait_for(check: Callable[[], Any], timeout: float, what: str, period: float = 0.05) -> Any:
    """The first truthy answer of ``check``, polled every ``period`` s; fails the test naming
    ``what`` after ``timeout`` s of wall time (the other process runs on its own clock)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        got = check()
        if got:
            return got
        time.sleep(period)
    pytest.fail(f"timed out waiting for {what}")
