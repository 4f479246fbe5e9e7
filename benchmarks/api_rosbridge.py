"""rosbridge benchmark: messages delivered to 20 subscribers of ``/scan`` and ``/tracked_pose``
and the latency of ``/rosapi/get_time`` calls, polynav beside a bare reference.

polynav runs as ``polynav run`` serves it: the simulated robot at real time on its loop thread,
the robot's streams and the androidmsg interface on a ROS graph, the rosbridge server on its own
event-loop thread. The reference is a bare ``websockets`` server that sends the same frames
(one scan and one pose as polynav wrote them) at the same 15 Hz to every subscriber and answers
``call_service`` at once, with nothing behind it. The clients run in a separate process
(this script with ``--load``), so they never share the servers' GIL. Run
``polynav bench api --dialect rosbridge [--clients 20] [--seconds 10] [--calls 500] [--json]``.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import platform
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

TOPICS = ("/scan", "/tracked_pose")
RATE = 15.0  # both topics, Hz


@contextmanager
def _polynav() -> Iterator[tuple[int, dict[str, str]]]:
    """polynav's rosbridge port, the robot running; and one frame of each topic."""
    from polynav.protocols.ros_graph import Graph
    from polynav.protocols.rosbridge import RosbridgeConfig, RosbridgeThread
    from polynav.protocols.rosbridge.androidmsg import add_androidmsg
    from polynav.protocols.rosbridge.robot_topics import add_robot_topics
    from polynav.protocols.rosbridge.wire import dumps
    from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
    from polynav.store.site_store import SiteStore
    from polynav.worlds import load_world

    world = load_world("demo")
    with tempfile.TemporaryDirectory() as tmp, SiteStore.open(
        Path(tmp) / "data", seed_world=world
    ) as store:
        runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=True))
        graph = Graph()
        detach = [add_robot_topics(graph, runtime), add_androidmsg(graph, runtime)]
        samples: dict[str, str] = {}

        def keep(name: str, message: dict[str, Any]) -> None:
            if name in TOPICS and name not in samples:
                samples[name] = dumps({"op": "publish", "topic": name, "msg": message})

        graph.add_sink(keep)
        for name in TOPICS:
            graph.retain(name)
        runtime.advance(0.5)
        for name in TOPICS:
            graph.release(name)
        runtime.start()
        server = RosbridgeThread(graph, runtime.clock, RosbridgeConfig(port=0))
        try:
            yield server.port, samples
        finally:
            server.stop()
            runtime.stop()
            for remove in detach:
                remove()


@contextmanager
def _reference(samples: dict[str, str]) -> Iterator[int]:
    """A bare rosbridge-like server sending ``samples`` at 15 Hz to its subscribers."""
    from websockets.asyncio.server import ServerConnection, serve
    from websockets.exceptions import ConnectionClosed

    loop = asyncio.new_event_loop()
    port: list[int] = []
    ready = threading.Event()
    stop = asyncio.Event()

    async def client(ws: ServerConnection) -> None:
        wanted: set[str] = set()

        async def pump() -> None:
            while True:
                for name in list(wanted):
                    await ws.send(samples[name])
                await asyncio.sleep(1.0 / RATE)

        task = asyncio.ensure_future(pump())
        try:
            async for frame in ws:
                data = json.loads(frame)
                if data.get("op") == "subscribe" and data.get("topic") in samples:
                    wanted.add(data["topic"])
                elif data.get("op") == "call_service":
                    now = time.monotonic()
                    await ws.send(json.dumps({
                        "op": "service_response", "service": data["service"],
                        "id": data.get("id"), "values": {"time": {
                            "secs": int(now), "nsecs": int((now % 1) * 1e9)}},
                        "result": True}))
        except ConnectionClosed:
            pass
        finally:
            task.cancel()

    async def main() -> None:
        async with serve(client, "127.0.0.1", 0, compression=None) as server:
            port.append(server.sockets[0].getsockname()[1])
            ready.set()
            await stop.wait()

    thread = threading.Thread(target=lambda: loop.run_until_complete(main()), daemon=True)
    thread.start()
    ready.wait(10)
    try:
        yield port[0]
    finally:
        loop.call_soon_threadsafe(stop.set)
        thread.join(10)
        loop.close()


# -- the load (a separate process) ---------------------------------------------------------------


async def _load(port: int, clients: int, seconds: float, calls: int) -> dict[str, Any]:
    from websockets.asyncio.client import connect

    counts = [dict.fromkeys(TOPICS, 0) for _ in range(clients)]

    async def subscriber(i: int) -> None:
        async with connect(f"ws://127.0.0.1:{port}", max_size=None, compression=None) as ws:
            for name in TOPICS:
                await ws.send(json.dumps({"op": "subscribe", "topic": name,
                                          "queue_length": 10}))
            end = time.monotonic() + seconds
            while (left := end - time.monotonic()) > 0:
                try:
                    frame = await asyncio.wait_for(ws.recv(), left)
                except TimeoutError:
                    break
                topic = json.loads(frame).get("topic")
                if topic in counts[i]:
                    counts[i][topic] += 1

    async def caller() -> list[float]:
        out = []
        async with connect(f"ws://127.0.0.1:{port}", compression=None) as ws:
            for n in range(calls):
                start = time.perf_counter()
                await ws.send(json.dumps({"op": "call_service", "id": f"t{n}",
                                          "service": "/rosapi/get_time"}))
                while True:
                    data = json.loads(await ws.recv())
                    if data.get("op") == "service_response" and data.get("id") == f"t{n}":
                        break
                out.append((time.perf_counter() - start) * 1000.0)
        return out

    await asyncio.gather(*(subscriber(i) for i in range(clients)))
    latencies = await caller()
    per = {name: [c[name] / seconds for c in counts] for name in TOPICS}
    ordered = sorted(latencies)
    return {
        "messages_per_second_min": {n: min(v) for n, v in per.items()},
        "messages_per_second_mean": {n: statistics.fmean(v) for n, v in per.items()},
        "get_time_p50_ms": ordered[len(ordered) // 2],
        "get_time_p99_ms": ordered[min(len(ordered) - 1, int(len(ordered) * 0.99))],
    }


def _measure(port: int, args: argparse.Namespace) -> dict[str, Any]:
    done = subprocess.run(
        [sys.executable, __file__, "--load", str(port), "--clients", str(args.clients),
         "--seconds", str(args.seconds), "--calls", str(args.calls)],
        capture_output=True, text=True, check=True, timeout=args.seconds * 4 + 120)
    result: dict[str, Any] = json.loads(done.stdout.strip().splitlines()[-1])
    return result


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="polynav bench api --dialect rosbridge",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, default=20, help="subscribers of both topics")
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--calls", type=int, default=500, help="/rosapi/get_time calls")
    parser.add_argument("--load", type=int, default=None, help=argparse.SUPPRESS)
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    args = parser.parse_args(argv)
    if args.clients < 1 or args.calls < 1 or not args.seconds > 0:
        parser.error("--clients, --calls and --seconds must be positive")
    if args.load is not None:
        print(json.dumps(asyncio.run(_load(args.load, args.clients, args.seconds, args.calls))))
        return 0
    with _polynav() as (port, samples):
        ours = _measure(port, args)
    with _reference(samples) as port:
        theirs = _measure(port, args)
    print(f"rosbridge: {args.clients} subscribers of {', '.join(TOPICS)} for {args.seconds:g} s "
          f"({RATE:g} Hz each), {args.calls} /rosapi/get_time calls; {platform.processor() or ''}"
          f" {platform.python_version()}")
    for name in TOPICS:
        print(f"{name}: messages/s per subscriber min {ours['messages_per_second_min'][name]:.1f}"
              f" mean {ours['messages_per_second_mean'][name]:.1f} (reference min "
              f"{theirs['messages_per_second_min'][name]:.1f})")
    print(f"/rosapi/get_time: p50 {ours['get_time_p50_ms']:.2f} ms, p99 "
          f"{ours['get_time_p99_ms']:.2f} ms (reference p50 {theirs['get_time_p50_ms']:.2f} ms, "
          f"p99 {theirs['get_time_p99_ms']:.2f} ms)")
    if args.json:
        print(json.dumps({"polynav": ours, "reference": theirs}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
