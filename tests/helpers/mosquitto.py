"""A real MQTT broker for tests: Eclipse Mosquitto on a free loopback port.

The broker is the Debian ``mosquitto`` package (CI installs it). Tests that need one must not
pass quietly without it, so a missing binary fails the test with how to install it, never skips.
The config is written to the test's tmp directory: one listener on 127.0.0.1 only, anonymous
clients allowed, persistence off (a restart forgets retained messages and sessions, like a
broker replaced by a new one). :meth:`Mosquitto.restart` stops the broker and starts it again
on the same port, for the tests of a transport that must reconnect.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import socket
import subprocess
import time
from pathlib import Path
from types import TracebackType

import pytest

START_TIMEOUT = 10.0
"""How long a broker may take to accept connections [s]."""

_SEARCH = ("/usr/sbin", "/usr/local/sbin", "/usr/bin")


def mosquitto_binary(name: str = "mosquitto") -> str:
    """The path of ``name`` (``mosquitto``, ``mosquitto_sub``); fails the test if absent."""
    found = shutil.which(name) or shutil.which(name, path=os.pathsep.join(_SEARCH))
    if found is None:
        pytest.fail(f"{name} is not installed: these tests need a real MQTT broker; "
                    "install it with `apt-get install mosquitto mosquitto-clients`", pytrace=False)
    return found


def free_loopback_port() -> int:
    """A TCP port free on 127.0.0.1 now (Mosquitto cannot listen on port 0 and say which)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
        return port


class Mosquitto:
    """One broker process; ``url`` is what :class:`~polynav.fleet.mqtt_transport.MqttTransport`
    takes. Use as a context manager, or :meth:`start` and :meth:`stop`."""

    def __init__(self, workdir: Path) -> None:
        self.workdir = workdir
        self.binary = mosquitto_binary()
        self.port = 0
        self.log_path = workdir / "mosquitto.log"
        self._process: subprocess.Popen[bytes] | None = None

    @property
    def url(self) -> str:
        return f"mqtt://127.0.0.1:{self.port}"

    @property
    def running(self) -> bool:
        return self._process is not None and self._process.poll() is None

    def start(self) -> None:
        """Start the broker (on a new free port the first time) and wait until it accepts."""
        if self.running:
            raise RuntimeError("the broker is already running")
        for _ in range(3):  # another process may take the free port before mosquitto binds it
            if self.port == 0:
                self.port = free_loopback_port()
            if self._try_start():
                return
            self.port = 0
        raise RuntimeError(f"mosquitto did not start; its log:\n{self.log()}")

    def stop(self) -> None:
        """Stop the broker (SIGTERM, then SIGKILL after 5 s); its clients see the socket close."""
        process, self._process = self._process, None
        if process is None:
            return
        if process.poll() is None:
            process.terminate()
            try:
                process.wait(timeout=5.0)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait(timeout=5.0)

    def restart(self) -> None:
        """Stop the broker and start a new one on the same port (retained messages are lost)."""
        self.stop()
        if not self._try_start():
            raise RuntimeError(f"mosquitto did not restart on port {self.port}; its log:\n"
                               f"{self.log()}")

    def log(self) -> str:
        """What the broker has written so far (connections, subscriptions, errors)."""
        with contextlib.suppress(FileNotFoundError):
            return self.log_path.read_text(encoding="utf-8", errors="replace")
        return ""

    def __enter__(self) -> Mosquitto:
        self.start()
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.stop()

    def _try_start(self) -> bool:
        config = self.workdir / "mosquitto.conf"
        lines = [
            f"listener {self.port} 127.0.0.1",
            "allow_anonymous true",
            "persistence false",
            "log_dest stderr",
            "log_type error",
            "log_type warning",
            "log_type notice",
            "log_type information",
            "connection_messages true",
        ]
        if os.geteuid() == 0:
            lines.append("user root")  # else mosquitto drops to a 'mosquitto' user
        config.write_text("\n".join(lines) + "\n", encoding="utf-8")
        with self.log_path.open("ab") as log:
            self._process = subprocess.Popen(
                [self.binary, "-c", str(config)], stdin=subprocess.DEVNULL,
                stdout=log, stderr=log,
            )
        deadline = time.monotonic() + START_TIMEOUT
        while time.monotonic() < deadline:
            if self._process.poll() is not None:  # e.g. the port was taken meanwhile
                self._process = None
                return False
            with contextlib.suppress(OSError), socket.create_connection(
                ("127.0.0.1", self.port), timeout=0.5
            ):
                return True
            time.sleep(0.02)
        self.stop()
        return False
