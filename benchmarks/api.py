"""Dialect API benchmark: commands per second and latency under many concurrent clients.

For the Yunji dialect: a polynav runtime (its loop thread running the simulated robot at real
time) serves the Yunji TCP API on an ephemeral loopback port; a separate client process opens
``--clients`` connections, each sending ``/api/robot_status`` and waiting for the reply in a loop
for ``--seconds``. Printed side by side with the same client load against a reference: a bare
asyncio server in this process that answers every line with a fixed reply of the same size (the
transport's ceiling on this machine, with no robot behind it).

Run with ``polynav bench api --dialect yunji [--clients 50] [--seconds 5] [--json]``.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import platform
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

COMMAND = b"/api/robot_status\n"


# -- the client load (runs in its own process: ``python api.py --load PORT CLIENTS SECONDS``) --


async def _one_client(port: int, deadline: float, latencies: list[float]) -> None:
    reader, writer = await asyncio.open_connection("127.0.0.1", port, limit=1 << 20)
    try:
        while time.perf_counter() < deadline:
            start = time.perf_counter()
            writer.write(COMMAND)
            await writer.drain()
            line = await reader.readline()
            if not line.endswith(b"\n"):
                raise ConnectionError("the server closed the connection")
            latencies.append(time.perf_counter() - start)
    finally:
        writer.close()


async def _load(port: int, clients: int, seconds: float) -> dict[str, Any]:
    latencies: list[float] = []
    deadline = time.perf_counter() + seconds
    began = time.perf_counter()
    await asyncio.gather(*(_one_client(port, deadline, latencies) for _ in range(clients)))
    elapsed = time.perf_counter() - began
    return {"count": len(latencies), "elapsed": elapsed, "latencies": sorted(latencies)}


def _run_load(port: int, clients: int, seconds: float) -> dict[str, Any]:
    """The load from a separate process, so the clients do not share the server's GIL."""
    out = subprocess.run(
        [sys.executable, str(Path(__file__).resolve()), "--load", str(port), str(clients),
         str(seconds)],
        capture_output=True, text=True, check=True, timeout=seconds + 120,
    )
    result: dict[str, Any] = json.loads(out.stdout)
    return result


# -- the servers -------------------------------------------------------------------------------


class _Reference:
    """A bare asyncio line server answering a fixed reply, on its own loop thread."""

    def __init__(self, reply: bytes) -> None:
        self._reply = reply
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._loop.run_forever, daemon=True)
        self._thread.start()
        self._server = asyncio.run_coroutine_threadsafe(self._start(), self._loop).result()

    async def _start(self) -> asyncio.Server:
        return await asyncio.start_server(self._handle, "127.0.0.1", 0)

    async def _handle(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            while await reader.readline():
                writer.write(self._reply)
                await writer.drain()
        except ConnectionError:
            pass
        finally:
            writer.close()

    @property
    def port(self) -> int:
        return int(self._server.sockets[0].getsockname()[1])

    def close(self) -> None:
        async def stop() -> None:
            self._server.close()
            await self._server.wait_closed()

        asyncio.run_coroutine_threadsafe(stop(), self._loop).result()
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join()
        self._loop.close()


def _figures(result: dict[str, Any]) -> dict[str, float]:
    lat = result["latencies"]
    if not lat:
        return {"commands_per_second": 0.0, "p50_ms": 0.0, "p95_ms": 0.0, "p99_ms": 0.0}

    def pct(q: float) -> float:
        return 1000.0 * lat[min(len(lat) - 1, int(q * len(lat)))]

    return {
        "commands_per_second": result["count"] / result["elapsed"],
        "p50_ms": pct(0.50),
        "p95_ms": pct(0.95),
        "p99_ms": pct(0.99),
    }


def _yunji(clients: int, seconds: float) -> tuple[dict[str, float], int]:
    from polynav.protocols.yunji import YunjiConfig
    from polynav.protocols.yunji.server import YunjiThread
    from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
    from polynav.store.site_store import SiteStore
    from polynav.worlds import load_world

    world = load_world("demo")
    with tempfile.TemporaryDirectory() as tmp, SiteStore.open(
        Path(tmp) / "data", seed_world=world
    ) as store:
        runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=True))
        runtime.start()
        server = YunjiThread(runtime, YunjiConfig(port=0, queue_size=1024))
        try:
            with socket.create_connection(("127.0.0.1", server.port)) as probe:
                probe.sendall(COMMAND)
                with probe.makefile("rb") as replies:
                    reply_size = len(replies.readline())
            result = _run_load(server.port, clients, seconds)
        finally:
            server.stop()
            runtime.stop()
    return _figures(result), reply_size


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="polynav bench api", description=__doc__.splitlines()[0])
    parser.add_argument("--dialect", choices=("yunji",), default="yunji")
    parser.add_argument("--clients", type=int, default=50)
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    args = parser.parse_args(argv)
    if args.clients < 1 or not args.seconds > 0.0:
        parser.error("--clients must be >= 1 and --seconds > 0")

    ours, reply_size = _yunji(args.clients, args.seconds)
    reference = _Reference(b"x" * (reply_size - 1) + b"\n")
    try:
        ceiling = _figures(_run_load(reference.port, args.clients, args.seconds))
    finally:
        reference.close()

    print(f"polynav bench api --dialect {args.dialect}: {args.clients} clients x "
          f"{args.seconds:g} s of /api/robot_status ({reply_size}-byte replies), "
          f"Python {platform.python_version()}")
    print(f"{'':34s}{'commands/s':>12s}{'p50 ms':>10s}{'p95 ms':>10s}{'p99 ms':>10s}")
    for label, row in (
        ("polynav yunji (TCP, live robot)", ours),
        ("reference: bare asyncio server", ceiling),
    ):
        print(f"{label:34s}{row['commands_per_second']:12.0f}{row['p50_ms']:10.2f}"
              f"{row['p95_ms']:10.2f}{row['p99_ms']:10.2f}")
    if args.json:
        print(json.dumps({"dialect": args.dialect, "clients": args.clients,
                          "seconds": args.seconds, "polynav": ours, "reference": ceiling}))
    return 0


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "--load":
        port, clients, seconds = int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
        print(json.dumps(asyncio.run(_load(port, clients, seconds))))
        sys.exit(0)
    sys.exit(main())
