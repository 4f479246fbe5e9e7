"""The client side of ``polynav bench api``, run in its own process so that the clients never
share the servers' GIL: ``python api_load.py KIND PORT CLIENTS SECONDS [options]``.

Kinds:

- ``line``: each client sends ``--line`` and reads one reply line, in a loop (the Yunji socket).
- ``get``: keep-alive HTTP/1.1; each client sends ``GET --path`` and reads the response, in a loop.
- ``paced``: keep-alive GET at a fixed total ``--rate`` spread over the clients (open loop: latency
  is counted from when a request was due, so a server that falls behind is not flattered).
- ``post``: keep-alive ``POST /api/points`` with a new point name each time.
- ``ws``: WebSocket subscribers to ``--path``; every status message's arrival and ``stamp``
  (native ``status``, or Puwei's O_STATUS ``time_stamp``).

The client is a few lines of asyncio over raw sockets (no HTTP library in the way), so the same
cheap client measures polynav and the reference. Prints one JSON object.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import sys
import time
from typing import Any


async def _read_response(reader: asyncio.StreamReader) -> int:
    head = await reader.readuntil(b"\r\n\r\n")
    status = int(head.split(b" ", 2)[1])
    length = 0
    for line in head.split(b"\r\n")[1:]:
        name, _, value = line.partition(b":")
        if name.strip().lower() == b"content-length":
            length = int(value)
    if length:
        await reader.readexactly(length)
    return status


def _request(method: str, path: str, body: bytes = b"", headers: tuple[str, ...] = ()
             ) -> bytes:
    head = f"{method} {path} HTTP/1.1\r\nHost: 127.0.0.1\r\n"
    for header in headers:
        head += f"{header}\r\n"
    if body:
        head += f"Content-Type: application/json\r\nContent-Length: {len(body)}\r\n"
    return head.encode() + b"\r\n" + body


class _Tally:
    def __init__(self) -> None:
        self.latencies: list[float] = []
        self.errors = 0


async def _line_client(port: int, line: bytes, deadline: float, tally: _Tally) -> None:
    reader, writer = await asyncio.open_connection("127.0.0.1", port, limit=1 << 20)
    try:
        while time.perf_counter() < deadline:
            start = time.perf_counter()
            writer.write(line)
            reply = await reader.readline()
            if not reply.endswith(b"\n"):
                raise ConnectionError("the server closed the connection")
            tally.latencies.append(time.perf_counter() - start)
    finally:
        writer.close()


async def _http_client(port: int, requests: Any, deadline: float, tally: _Tally,
                       period: float | None, phase: float) -> None:
    reader, writer = await asyncio.open_connection("127.0.0.1", port, limit=1 << 22)
    due = time.perf_counter() + phase
    try:
        for request in requests:
            if period is not None:
                await asyncio.sleep(max(0.0, due - time.perf_counter()))
                start = due
                due += period
            else:
                start = time.perf_counter()
            if start >= deadline:
                break
            writer.write(request)
            status = await _read_response(reader)
            if status >= 400:
                tally.errors += 1
            tally.latencies.append(time.perf_counter() - start)
    finally:
        writer.close()


def _gets(path: str, headers: tuple[str, ...] = ()) -> Any:
    request = _request("GET", path, headers=headers)
    while True:
        yield request


def _posts(client: int) -> Any:
    number = 0
    while True:
        number += 1
        body = json.dumps({"name": f"bench-{client}-{number}", "map": "floor1",
                           "x": 1.0 + 0.001 * number, "y": 2.0, "theta": 0.5}).encode()
        yield _request("POST", "/api/points", body)


async def _ws_client(port: int, path: str, deadline: float, frames: list[list[float]]) -> None:
    from websockets.asyncio.client import connect

    mine: list[float] = []
    frames.append(mine)
    async with connect(f"ws://127.0.0.1:{port}{path}", max_size=1 << 22,
                       ping_interval=None) as socket:
        while True:
            left = deadline - time.perf_counter()
            if left <= 0.0:
                break
            try:
                text = await asyncio.wait_for(socket.recv(), left)
            except asyncio.TimeoutError:
                break
            arrived = time.perf_counter()
            message = json.loads(text)
            if message.get("type") == "status":
                mine.extend((arrived, float(message["data"]["stamp"])))
            elif message.get("type") == 1026:  # Puwei's O_STATUS: milliseconds of its calendar
                mine.extend((arrived, float(message["data"]["time_stamp"]) / 1000.0))


def _lag_figures(frames: list[list[float]], seconds: float) -> dict[str, Any]:
    """Per subscriber: messages per second, and the lag of each message against the first one's
    (the robot's clock runs at real time, so a growing lag is a server falling behind)."""
    rates, first_lags, last_lags, worst = [], [], [], 0.0
    for pairs in frames:
        arrivals, stamps = pairs[0::2], pairs[1::2]
        if len(arrivals) < 4:
            rates.append(0.0)
            continue
        rates.append(len(arrivals) / seconds)
        lags = [(a - arrivals[0]) - (s - stamps[0]) for a, s in zip(arrivals, stamps, strict=True)]
        tenth = max(1, len(lags) // 10)
        first_lags.append(sum(lags[:tenth]) / tenth)
        last_lags.append(sum(lags[-tenth:]) / tenth)
        worst = max(worst, max(lags) - min(lags))
    count = max(1, len(first_lags))
    return {
        "subscribers": len(frames),
        "messages_per_second_min": min(rates) if rates else 0.0,
        "messages_per_second_mean": sum(rates) / max(1, len(rates)),
        "lag_growth_ms": 1000.0 * (sum(last_lags) - sum(first_lags)) / count,
        "lag_spread_ms": 1000.0 * worst,
    }


async def run(args: argparse.Namespace) -> dict[str, Any]:
    tally = _Tally()
    deadline = time.perf_counter() + args.seconds
    began = time.perf_counter()
    if args.kind == "ws":
        frames: list[list[float]] = []
        await asyncio.gather(*(_ws_client(args.port, args.path, deadline, frames)
                               for _ in range(args.clients)))
        return _lag_figures(frames, time.perf_counter() - began)
    if args.kind == "line":
        line = args.line.encode() + b"\n"
        clients = [_line_client(args.port, line, deadline, tally) for _ in range(args.clients)]
    else:
        period = args.clients / args.rate if args.kind == "paced" else None
        clients = [
            _http_client(
                args.port,
                _posts(n) if args.kind == "post" else _gets(args.path, tuple(args.header)),
                deadline, tally, period,
                phase=(n * period / args.clients) if period else 0.0,
            )
            for n in range(args.clients)
        ]
    await asyncio.gather(*clients)
    return {"count": len(tally.latencies), "errors": tally.errors,
            "elapsed": time.perf_counter() - began, "latencies": sorted(tally.latencies)}


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="api_load.py", description=__doc__.splitlines()[0])
    parser.add_argument("kind", choices=("line", "get", "paced", "post", "ws"))
    parser.add_argument("port", type=int)
    parser.add_argument("clients", type=int)
    parser.add_argument("seconds", type=float)
    parser.add_argument("--path", default="/api/status")
    parser.add_argument("--line", default="/api/robot_status")
    parser.add_argument("--header", action="append", default=[], metavar="NAME: VALUE",
                        help="a request header for get and paced loads (repeat)")
    parser.add_argument("--rate", type=float, default=1000.0, help="total requests/s (paced)")
    args = parser.parse_args(argv)
    print(json.dumps(asyncio.run(run(args))))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
