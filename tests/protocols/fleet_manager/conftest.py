"""A real Mosquitto for each test, and ``polynav fleet`` as a user starts it: its own process on
that broker, its API on a free loopback port, stopped by SIGINT (and killed if the test did not
stop it)."""

from __future__ import annotations

import re
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.helpers.mosquitto import Mosquitto
from tests.helpers.postgres import (  # noqa: F401  (fixtures)
    postgres_database,
    postgres_server,
    postgres_url,
)


@pytest.fixture
def broker(tmp_path: Path) -> Iterator[Mosquitto]:
    with Mosquitto(tmp_path) as running:
        yield running


class FleetProcess:
    """One ``polynav fleet`` process; :attr:`url` is its API's base (``http://host:port``)."""

    def __init__(self, args: list[str]) -> None:
        self.proc = subprocess.Popen([sys.executable, "-m", "polynav", "fleet", *args],
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.lines: list[str] = []
        self.url = ""
        assert self.proc.stdout is not None
        while len(self.lines) < 10:
            line = self.proc.stdout.readline()
            if not line:
                break
            self.lines.append(line.rstrip("\n"))
            found = re.search(r"API (http://[\d.]+:\d+)/api", line)
            if found:
                self.url = found.group(1)
                return

    def stop(self) -> tuple[int, str]:
        """SIGINT, then its exit status and standard error."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        try:
            _, err = self.proc.communicate(timeout=20.0)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            _, err = self.proc.communicate()
        return self.proc.returncode, err


@pytest.fixture
def start_fleet() -> Iterator[list[FleetProcess]]:
    """A list to append started fleet processes to; each is stopped at the end."""
    started: list[FleetProcess] = []
    yield started
    for fleet in started:
        if fleet.proc.poll() is None:
            fleet.proc.kill()
            fleet.proc.communicate()
