"""``polynav run --broker embedded``: an MQTT broker inside the process (issue #36 item 4).

A user who wants to watch the fleet's VDA 5050 traffic with ``mosquitto_sub`` should not have
to install and configure a broker first. :class:`EmbeddedBroker` runs amqtt's MQTT 3.1.1 broker
on a thread of its own (its own asyncio loop, apart from the servers' loop), on 127.0.0.1 only,
anonymous clients allowed; the robots and the master control then connect to its
``mqtt://127.0.0.1:<port>`` exactly as to any other broker: the transport is the same paho
client, only the URL was found here.

The broker keeps nothing on disk and lives as long as the process: it is for one machine and
for watching, not for a site (which runs Mosquitto or another broker of its own; docs/fleet.md).
"""

from __future__ import annotations

import argparse
import asyncio
import logging
import threading
from types import TracebackType
from typing import Any

from polynav.errors import PolynavError

log = logging.getLogger(__name__)

EMBEDDED = "embedded"
"""The ``--broker`` value that asks for a broker in the process."""

HOST = "127.0.0.1"
"""The embedded broker listens on loopback only."""

START_TIMEOUT = 10.0
"""How long the broker may take to listen [s]."""

STOP_TIMEOUT = 5.0
"""How long the broker may take to say goodbye to its clients and stop [s]."""


class BrokerStartError(PolynavError):
    """The embedded broker could not listen (its port taken, say)."""


class EmbeddedBroker:
    """An amqtt broker on its own thread (see the module docstring).

    Args:
        port: the TCP port on 127.0.0.1; 0 for any free one (:attr:`port` then tells which).

    Raises:
        BrokerStartError: it could not listen within :data:`START_TIMEOUT`.
    """

    def __init__(self, port: int = 1883) -> None:
        if not 0 <= port <= 65535:
            raise BrokerStartError(f"embedded MQTT broker: port {port} is not a TCP port")
        self._loop = asyncio.new_event_loop()
        self._ready = threading.Event()
        self._failure: BaseException | None = None
        self._broker: Any = None
        self._closed = False
        self.port = 0
        # amqtt logs every connection and subscription at INFO; polynav's log is about robots.
        quiet = logging.getLogger("amqtt")
        if quiet.level == logging.NOTSET:
            quiet.setLevel(logging.WARNING)
        # A failed start is said once, in one line, by BrokerStartError, not with amqtt's trace.
        logging.getLogger("amqtt.broker").addFilter(_no_startup_trace)
        self._thread = threading.Thread(target=self._run, args=(port,), daemon=True,
                                        name="mqtt-broker")
        self._thread.start()
        if not self._ready.wait(START_TIMEOUT):
            self.close()
            raise BrokerStartError(f"embedded MQTT broker on {HOST}:{port} did not start "
                                   f"within {START_TIMEOUT:g} s")
        if self._failure is not None:
            reason = self._failure.__cause__ or self._failure
            self._thread.join(STOP_TIMEOUT)
            self._loop.close()
            self._closed = True
            raise BrokerStartError(f"cannot start the embedded MQTT broker on {HOST}:{port}: "
                                   f"{' '.join(str(reason).split())}")
        log.info("embedded MQTT broker on %s", self.url)

    @property
    def url(self) -> str:
        """Where clients connect: ``mqtt://127.0.0.1:<port>``."""
        return f"mqtt://{HOST}:{self.port}"

    def close(self) -> None:
        """Stop the broker (its clients see the connection close) and its thread; idempotent."""
        if self._closed:
            return
        self._closed = True
        if self._broker is not None and self._loop.is_running():
            done = asyncio.run_coroutine_threadsafe(self._broker.shutdown(), self._loop)
            try:
                done.result(STOP_TIMEOUT)
            except Exception:  # a broker that fails to stop cleanly is still stopped below
                log.warning("embedded MQTT broker did not shut down cleanly", exc_info=True)
        if self._loop.is_running():
            self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join(STOP_TIMEOUT)
        if not self._thread.is_alive():
            self._loop.close()
        log.info("embedded MQTT broker stopped")

    def __enter__(self) -> EmbeddedBroker:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.close()

    # -- the broker's thread ---------------------------------------------------------------

    def _run(self, port: int) -> None:
        asyncio.set_event_loop(self._loop)
        try:
            self._loop.run_until_complete(self._start(port))
        except Exception as exc:  # reported to the constructor, which raises it
            self._failure = exc
            self._ready.set()
            return
        self._ready.set()
        try:
            self._loop.run_forever()
        finally:
            pending = [t for t in asyncio.all_tasks(self._loop) if not t.done()]
            for task in pending:
                task.cancel()
            if pending:
                self._loop.run_until_complete(
                    asyncio.gather(*pending, return_exceptions=True))

    async def _start(self, port: int) -> None:
        from amqtt.broker import Broker  # imported here: only `--broker embedded` needs it

        broker = Broker({
            "listeners": {"default": {"type": "tcp", "bind": f"{HOST}:{port}"}},
            # Anonymous clients only; no $SYS topics, no packet log.
            "plugins": {"amqtt.plugins.authentication.AnonymousAuthPlugin":
                        {"allow_anonymous": True}},
        })
        await broker.start()
        self._broker = broker
        sockets = broker._servers["default"].instance.sockets  # amqtt has no public accessor
        self.port = int(sockets[0].getsockname()[1])


def _no_startup_trace(record: logging.LogRecord) -> bool:
    return not record.getMessage().startswith("Broker startup failed")


def resolve(args: argparse.Namespace) -> EmbeddedBroker | None:
    """``polynav run``'s ``--broker``: with ``embedded``, start the broker on
    ``--broker-port`` and put its URL in ``args.broker`` (the robots then connect to it as to
    any broker); otherwise leave ``args`` as it is. The caller closes what is returned.

    Raises:
        BrokerStartError: the embedded broker could not listen.
    """
    if args.broker != EMBEDDED:
        return None
    broker = EmbeddedBroker(int(args.broker_port))
    args.broker = broker.url
    return broker


def banner(broker: EmbeddedBroker) -> str:
    """The start-up line that says where the embedded broker is and how to watch it."""
    return (f"embedded MQTT broker on {broker.url} (watch: mosquitto_sub -h {HOST} "
            f"-p {broker.port} -t 'uagv/v2/#' -v)")
