"""API benchmark: polynav's servers beside bare references, under the same client load.

polynav runs as ``polynav run`` does (the simulated robot at real time, walkers on, the native
API under uvicorn, the Yunji TCP server); a separate client process (``api_load.py``) drives:

- native keep-alive ``GET /api/status`` as fast as the clients go, and paced at ``--rate``
  requests/s (open loop: the p99 that DESIGN.md §8 bounds);
- native ``POST /api/points`` (a new point each time, written to the site store);
- native WebSocket fan-out: ``--ws-clients`` subscribers to ``/api/ws?rate=15``: messages per
  second and whether their lag grows over ``--ws-seconds``;
- Yunji ``/api/robot_status`` on its TCP socket.

The references run after polynav has stopped, with nothing behind them: a bare uvicorn + FastAPI
app answering the same JSON (a fixed status body, a pydantic-validated point echoed back, a
status message per 1/15 s per subscriber), and a bare asyncio line server answering replies of
the same size as Yunji's. Run ``polynav bench api [--only native|yunji ...] [--json]``.
"""

from __future__ import annotations

import argparse
import asyncio
import http.client
import json
import platform
import socket
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from fastapi import FastAPI, WebSocket, WebSocketDisconnect
from fastapi.responses import JSONResponse
from pydantic import BaseModel

LOAD = Path(__file__).resolve().with_name("api_load.py")
YUNJI_COMMAND = b"/api/robot_status\n"
WS_RATE = 15.0


def _load(kind: str, port: int, clients: int, seconds: float, *extra: str) -> dict[str, Any]:
    """One client load from its own process, so the clients never share the server's GIL."""
    out = subprocess.run(
        [sys.executable, str(LOAD), kind, str(port), str(clients), str(seconds), *extra],
        capture_output=True, text=True, timeout=seconds + 120,
    )
    if out.returncode != 0:
        raise RuntimeError(f"the {kind} load failed: {out.stderr.strip()[-2000:]}")
    result: dict[str, Any] = json.loads(out.stdout)
    return result


def _figures(result: dict[str, Any]) -> dict[str, float]:
    lat = result["latencies"]

    def pct(q: float) -> float:
        return 1000.0 * lat[min(len(lat) - 1, int(q * len(lat)))] if lat else 0.0

    return {
        "per_second": result["count"] / result["elapsed"],
        "errors": result["errors"],
        "p50_ms": pct(0.50),
        "p99_ms": pct(0.99),
    }


# -- servers -----------------------------------------------------------------------------------


class _Uvicorn:
    """An ASGI app under uvicorn on a loopback TCP_NODELAY socket, in a thread."""

    def __init__(self, app: Any) -> None:
        import uvicorn

        from polynav.listen import tcp_listener

        self._sock = tcp_listener("127.0.0.1", 0)
        self.port = int(self._sock.getsockname()[1])
        self._server = uvicorn.Server(
            uvicorn.Config(app, log_level="warning", lifespan="off", ws="websockets-sansio")
        )
        self._thread = threading.Thread(
            target=self._server.run, kwargs={"sockets": [self._sock]}, daemon=True
        )
        self._thread.start()
        while not self._server.started:  # uvicorn has no start callback: wait for its flag
            if not self._thread.is_alive():
                raise RuntimeError("uvicorn did not start")
            time.sleep(0.005)

    def close(self) -> None:
        self._server.should_exit = True
        self._thread.join(timeout=30.0)
        self._sock.close()


class Point(BaseModel):
    name: str
    map: str
    x: float
    y: float
    theta: float = 0.0


def _bare_fastapi(status: dict[str, Any]) -> Any:
    """The reference app: the same routes answering the same JSON, with no robot behind them."""
    app = FastAPI()

    @app.get("/api/status")
    def get_status() -> JSONResponse:
        return JSONResponse(status)

    @app.post("/api/points", status_code=201)
    def create_point(point: Point) -> dict[str, Any]:
        return {**point.model_dump(), "kind": "general", "number": None, "floor": "1"}

    @app.websocket("/api/ws")
    async def stream(websocket: WebSocket, rate: float = WS_RATE) -> None:
        await websocket.accept()
        began = time.perf_counter()
        beat = 0
        try:
            while True:
                beat += 1
                await asyncio.sleep(max(0.0, began + beat / rate - time.perf_counter()))
                data = {**status, "stamp": time.perf_counter() - began}
                await websocket.send_json({"type": "status", "data": data})
        except (WebSocketDisconnect, RuntimeError):
            pass

    return app


class _BareLineServer:
    """A bare asyncio line server answering a fixed reply, on its own loop thread."""

    def __init__(self, reply: bytes) -> None:
        self._reply = reply
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._loop.run_forever, daemon=True)
        self._thread.start()
        self._server = asyncio.run_coroutine_threadsafe(self._start(), self._loop).result()
        self.port = int(self._server.sockets[0].getsockname()[1])

    async def _start(self) -> asyncio.Server:
        from polynav.listen import tcp_listener

        return await asyncio.start_server(self._handle, sock=tcp_listener("127.0.0.1", 0))

    async def _handle(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            while await reader.readline():
                writer.write(self._reply)
                await writer.drain()
        except ConnectionError:
            pass
        finally:
            writer.close()

    def close(self) -> None:
        async def stop() -> None:
            self._server.close()
            await self._server.wait_closed()

        asyncio.run_coroutine_threadsafe(stop(), self._loop).result()
        self._loop.call_soon_threadsafe(self._loop.stop)
        self._thread.join()
        self._loop.close()


@contextmanager
def _polynav(with_yunji: bool) -> Iterator[tuple[int, int | None]]:
    """polynav as ``polynav run`` serves it: (native API port, Yunji TCP port or None)."""
    from polynav.api import ApiConfig, create_app
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
        api = _Uvicorn(create_app(runtime, ApiConfig(port=0)))
        yunji = YunjiThread(runtime, YunjiConfig(port=0, queue_size=1024)) if with_yunji else None
        try:
            yield api.port, (yunji.port if yunji is not None else None)
        finally:
            if yunji is not None:
                yunji.stop()
            api.close()
            runtime.stop()


def _get_json(port: int, path: str) -> dict[str, Any]:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    try:
        connection.request("GET", path)
        body: dict[str, Any] = json.loads(connection.getresponse().read())
        return body
    finally:
        connection.close()


def _yunji_reply_size(port: int) -> int:
    with socket.create_connection(("127.0.0.1", port)) as probe:
        probe.sendall(YUNJI_COMMAND)
        with probe.makefile("rb") as replies:
            return len(replies.readline())


# -- the runs ----------------------------------------------------------------------------------


def _native_loads(args: argparse.Namespace) -> list[tuple[str, Callable[[int], dict[str, Any]]]]:
    http_clients, seconds = args.http_clients, args.seconds
    return [
        ("GET /api/status keep-alive",
         lambda port: _figures(_load("get", port, http_clients, seconds))),
        (f"GET /api/status at {args.rate:g}/s",
         lambda port: _figures(_load("paced", port, http_clients, seconds,
                                     "--rate", str(args.rate)))),
        ("POST /api/points",
         lambda port: _figures(_load("post", port, http_clients, seconds))),
        (f"WS fan-out x{args.ws_clients} at {WS_RATE:g} Hz",
         lambda port: _load("ws", port, args.ws_clients, args.ws_seconds,
                            "--path", f"/api/ws?rate={WS_RATE:g}")),
    ]


def run(args: argparse.Namespace) -> dict[str, Any]:
    """Every figure, polynav first (robot running), then the references (nothing running)."""
    ours: dict[str, Any] = {}
    theirs: dict[str, Any] = {}
    native = "native" in args.only
    yunji = "yunji" in args.only
    with _polynav(with_yunji=yunji) as (api_port, yunji_port):
        status = _get_json(api_port, "/api/status")
        if native:
            for label, load in _native_loads(args):
                ours[label] = load(api_port)
        if yunji_port is not None:
            reply_size = _yunji_reply_size(yunji_port)
            ours["yunji robot_status"] = _figures(
                _load("line", yunji_port, args.clients, args.seconds))
    if native:
        reference = _Uvicorn(_bare_fastapi(status))
        try:
            for label, load in _native_loads(args):
                theirs[label] = load(reference.port)
        finally:
            reference.close()
    if yunji:
        line_server = _BareLineServer(b"x" * (reply_size - 1) + b"\n")
        try:
            theirs["yunji robot_status"] = _figures(
                _load("line", line_server.port, args.clients, args.seconds))
        finally:
            line_server.close()
    return {"polynav": ours, "reference": theirs}


def _print(args: argparse.Namespace, figures: dict[str, Any]) -> None:
    ours, theirs = figures["polynav"], figures["reference"]
    print(f"polynav bench api: {args.http_clients} HTTP clients, {args.clients} Yunji clients, "
          f"{args.seconds:g} s per load; WebSocket {args.ws_seconds:g} s; "
          f"Python {platform.python_version()}")
    print("references: bare uvicorn + FastAPI (same JSON), bare asyncio line server (same size)")
    print(f"{'':34s}{'polynav/s':>11s}{'ref/s':>10s}{'ratio':>7s}"
          f"{'p50 ms':>8s}{'p99 ms':>8s}{'ref p99':>9s}{'errors':>7s}")
    for label, row in ours.items():
        ref = theirs[label]
        if "per_second" not in row:
            continue
        ratio = row["per_second"] / ref["per_second"] if ref["per_second"] else 0.0
        print(f"{label:34s}{row['per_second']:11.0f}{ref['per_second']:10.0f}{ratio:7.2f}"
              f"{row['p50_ms']:8.2f}{row['p99_ms']:8.2f}{ref['p99_ms']:9.2f}{row['errors']:7d}")
    for label, row in ours.items():
        if "subscribers" not in row:
            continue
        ref = theirs[label]
        print(f"{label}: messages/s per subscriber min {row['messages_per_second_min']:.1f} "
              f"(reference {ref['messages_per_second_min']:.1f}), lag growth "
              f"{row['lag_growth_ms']:+.1f} ms (reference {ref['lag_growth_ms']:+.1f}), "
              f"lag spread {row['lag_spread_ms']:.1f} ms (reference {ref['lag_spread_ms']:.1f})")


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    dialects = ("native", "yunji", "galileo", "galileo-wire", "puwei", "rosbridge")
    pre = argparse.ArgumentParser(add_help=False)
    pre.add_argument("--dialect", choices=dialects)
    chosen, argv = pre.parse_known_args(argv)
    if chosen.dialect == "galileo":  # its own load and reference (api_galileo.py)
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from api_galileo import main as galileo_main

        return galileo_main(argv)
    if chosen.dialect == "galileo-wire":  # serial, Modbus, UDP fast (api_galileo_wire.py)
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from api_galileo_wire import main as galileo_wire_main

        return galileo_wire_main(argv)
    if chosen.dialect == "puwei":  # its own load, login and reference (api_puwei.py)
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from api_puwei import main as puwei_main

        return puwei_main(argv)
    if chosen.dialect == "rosbridge":  # subscribers and calls (api_rosbridge.py)
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from api_rosbridge import main as rosbridge_main

        return rosbridge_main(argv)
    if chosen.dialect is not None:
        argv += ["--only", chosen.dialect]
    parser = argparse.ArgumentParser(prog="polynav bench api", description=__doc__.splitlines()[0])
    parser.add_argument("--dialect", choices=dialects,
                        help="one server (galileo, puwei: a status GET under 50 clients; "
                             "rosbridge: 20 subscribers and get_time calls; galileo-wire: "
                             "serial frames, Modbus reads, UDP fan-out; their own "
                             "options: --dialect galileo --help)")
    parser.add_argument("--only", nargs="+", choices=("native", "yunji"),
                        default=["native", "yunji"], help="which servers (default: all)")
    parser.add_argument("--clients", type=int, default=50, help="Yunji connections")
    parser.add_argument("--http-clients", type=int, default=10, help="keep-alive connections")
    parser.add_argument("--seconds", type=float, default=5.0, help="per load")
    parser.add_argument("--rate", type=float, default=1000.0, help="paced GETs per second")
    parser.add_argument("--ws-clients", type=int, default=50)
    parser.add_argument("--ws-seconds", type=float, default=10.0,
                        help="WebSocket run (the target is stated over 300)")
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    args = parser.parse_args(argv)
    if min(args.clients, args.http_clients, args.ws_clients) < 1:
        parser.error("client counts must be >= 1")
    if not (args.seconds > 0.0 and args.ws_seconds > 0.0 and args.rate > 0.0):
        parser.error("--seconds, --ws-seconds and --rate must be > 0")
    figures = run(args)
    _print(args, figures)
    if args.json:
        print(json.dumps({"clients": args.clients, "http_clients": args.http_clients,
                          "seconds": args.seconds, "ws_seconds": args.ws_seconds, **figures}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
