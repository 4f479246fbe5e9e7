"""Galileo wire protocols benchmark: the serial status frames' rate and jitter over a pty, Modbus
register reads under concurrent clients beside a bare pymodbus server, and the UDP fast
protocol's status fan-out.

polynav runs as ``polynav run`` serves it (the simulated robot at real time, walkers on, the
Galileo servers on their own event-loop thread). Every client runs in a separate process (this
script with ``--load ...``), so no client shares the server's GIL:

* **serial**: a host reads the pty for ``--seconds``: frames per second (target 30) and the p99
  of how far each frame's arrival is from the 30 Hz beat (``|gap - 33.3 ms|``).
* **modbus**: ``--modbus-clients`` connections each reading the 27 input registers (every
  status value) in a loop: reads per second and p50/p99, polynav beside a bare pymodbus server
  (a static register block, nothing behind it) in the same run.
* **udp**: ``--udp-clients`` UDP fast clients subscribed to ``/galileo/status`` (10 Hz each).

Run ``polynav bench api --dialect galileo-wire [--seconds 5] [--modbus-clients 20]
[--udp-clients 20] [--json]``.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import logging
import platform
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

FRAME_PERIOD = 1.0 / 30.0
REGISTERS = 27  # the input registers: every status value


@contextmanager
def _polynav(udp_fast: bool) -> Iterator[Any]:
    """polynav's Galileo servers (serial on a pty, Modbus, UDP fast) around a running robot."""
    from polynav.protocols.galileo import GalileoConfig
    from polynav.protocols.galileo.server import GalileoThread
    from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
    from polynav.store.site_store import SiteStore
    from polynav.worlds import load_world

    world = load_world("demo")
    with tempfile.TemporaryDirectory() as tmp, SiteStore.open(
        Path(tmp) / "data", seed_world=world
    ) as store:
        runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=True))
        runtime.start()
        options: dict[str, Any] = {"port": 0, "ws_port": None, "announce": False,
                                   "serial": "pty", "modbus_port": 0}
        if udp_fast:
            options["udp_fast_port"] = 0
        galileo = GalileoThread(runtime, GalileoConfig(**options))
        try:
            yield galileo
        finally:
            galileo.stop()
            runtime.stop()


@contextmanager
def _bare_modbus() -> Iterator[int]:
    """A pymodbus TCP server over a static block of the same size: the reference."""
    from pymodbus.datastore import (
        ModbusDeviceContext,
        ModbusSequentialDataBlock,
        ModbusServerContext,
    )
    from pymodbus.server import ModbusTcpServer

    logging.getLogger("pymodbus").setLevel(logging.ERROR)  # its 3.x context's v4 notice
    device = ModbusDeviceContext(ir=ModbusSequentialDataBlock(1, [7] * (REGISTERS + 1)))
    context = ModbusServerContext(devices=device, single=True)
    loop = asyncio.new_event_loop()
    servers: list[ModbusTcpServer] = []
    started = threading.Event()

    def serve() -> None:
        asyncio.set_event_loop(loop)

        async def main() -> None:
            servers.append(ModbusTcpServer(context, address=("127.0.0.1", 0)))
            await servers[0].serve_forever(background=True)
            started.set()

        loop.run_until_complete(main())
        loop.run_forever()

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    started.wait(10)
    server = servers[0]
    port = int(server.transport.sockets[0].getsockname()[1])  # type: ignore[attr-defined]
    try:
        yield port
    finally:
        asyncio.run_coroutine_threadsafe(server.shutdown(), loop).result(10)  # type: ignore[no-untyped-call]
        loop.call_soon_threadsafe(loop.stop)
        thread.join(10)


# -- the loads (each in its own process) ---------------------------------------------------------


def _load_serial(path: str, seconds: float) -> dict[str, Any]:
    import serial

    from polynav.protocols.galileo.native.commands import HEADER
    from polynav.protocols.galileo.native.status_frame import STATUS_FRAME_SIZE

    arrivals: list[float] = []
    buffer = b""
    with serial.Serial(path, 115200, timeout=0.01) as port:
        port.reset_input_buffer()
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            chunk = port.read(max(1, port.in_waiting))
            now = time.monotonic()
            buffer += chunk
            while True:
                start = buffer.find(HEADER)
                if start < 0 or len(buffer) - start < STATUS_FRAME_SIZE:
                    break
                arrivals.append(now)
                buffer = buffer[start + STATUS_FRAME_SIZE:]
    return {"arrivals": arrivals, "seconds": seconds}


def _load_modbus(port: int, clients: int, seconds: float) -> dict[str, Any]:
    from pymodbus.client import ModbusTcpClient

    latencies: list[float] = []
    errors = 0
    lock = threading.Lock()
    start_at = time.monotonic() + 0.5

    def one() -> None:
        nonlocal errors
        mine: list[float] = []
        bad = 0
        with ModbusTcpClient("127.0.0.1", port=port, timeout=10, retries=0) as client:
            while time.monotonic() < start_at:
                time.sleep(0.001)
            while time.monotonic() < start_at + seconds:
                t0 = time.perf_counter()
                reply = client.read_input_registers(0, count=REGISTERS)
                mine.append(time.perf_counter() - t0)
                bad += reply.isError()
        with lock:
            latencies.extend(mine)
            errors += bad

    threads = [threading.Thread(target=one) for _ in range(clients)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    latencies.sort()
    return {"count": len(latencies), "elapsed": seconds, "errors": errors,
            "latencies": latencies}


def _load_udp(port: int, clients: int, seconds: float) -> dict[str, Any]:
    """``clients`` UDP fast subscribers of ``/galileo/status`` (spec §4: register, then count the
    TEXT frames, answering the server's pings) on one thread with ``select``."""
    import select
    import socket

    socks = []
    for _ in range(clients):
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        sock.sendto(b"\x01udp://127.0.0.1:%d/galileo/status\x00" % port, ("127.0.0.1", port))
        socks.append(sock)
    ids: dict[socket.socket, bytes] = {}
    counts = {sock: 0 for sock in socks}
    start = time.monotonic()
    window = start + 0.5  # registration and the first messages first
    end = window + seconds
    while time.monotonic() < end:
        ready, _, _ = select.select(socks, [], [], 0.05)
        now = time.monotonic()
        for sock in ready:
            data = sock.recv(4096)
            if len(data) < 6 or data[0] != 2:
                continue
            if sock not in ids:
                if json.loads(data[6:]).get("status"):
                    ids[sock] = data[1:5]
                continue
            opcode = data[5]
            if opcode == 9:  # ping: pong
                sock.sendto(b"\x02" + ids[sock] + b"\x0a", ("127.0.0.1", port))
            elif opcode == 1 and now >= window:
                counts[sock] += 1
    for sock in socks:
        if sock in ids:
            sock.sendto(b"\x02" + ids[sock] + b"\x08", ("127.0.0.1", port))
        sock.close()
    return {"per_client": list(counts.values()), "seconds": seconds,
            "registered": len(ids)}


def _run_load(*argv: str, timeout: float) -> dict[str, Any]:
    out = subprocess.run([sys.executable, __file__, "--load", *argv], capture_output=True,
                         text=True, timeout=timeout)
    if out.returncode != 0:
        raise RuntimeError(f"the {argv[0]} load failed: {out.stderr.strip()[-2000:]}")
    result: dict[str, Any] = json.loads(out.stdout)
    return result


# -- figures -------------------------------------------------------------------------------------


def _percentile(values: list[float], q: float) -> float:
    return values[min(len(values) - 1, int(q * len(values)))] if values else 0.0


def _serial_figures(result: dict[str, Any]) -> dict[str, float]:
    arrivals = result["arrivals"]
    gaps = [b - a for a, b in zip(arrivals, arrivals[1:], strict=False)]
    off_beat = sorted(abs(g - FRAME_PERIOD) for g in gaps)
    span = arrivals[-1] - arrivals[0] if len(arrivals) > 1 else 0.0
    return {"frames_per_second": (len(arrivals) - 1) / span if span > 0 else 0.0,
            "jitter_p50_ms": 1000.0 * _percentile(off_beat, 0.5),
            "jitter_p99_ms": 1000.0 * _percentile(off_beat, 0.99)}


def _modbus_figures(result: dict[str, Any]) -> dict[str, float]:
    lat = result["latencies"]
    return {"per_second": result["count"] / result["elapsed"], "errors": result["errors"],
            "p50_ms": 1000.0 * _percentile(lat, 0.5), "p99_ms": 1000.0 * _percentile(lat, 0.99)}


def run(args: argparse.Namespace) -> dict[str, Any]:
    udp = args.udp_clients > 0
    with _polynav(udp) as galileo:
        path = galileo.serial_path
        serial = _serial_figures(_run_load("serial", path, str(args.seconds),
                                           timeout=args.seconds + 60))
        ours = _modbus_figures(_run_load("modbus", str(galileo.modbus_port),
                                         str(args.modbus_clients), str(args.seconds),
                                         timeout=args.seconds + 120))
        fan_out: dict[str, Any] | None = None
        if udp:
            result = _run_load("udp", str(galileo.udp_fast_port), str(args.udp_clients),
                               str(args.seconds), timeout=args.seconds + 60)
            rates = [n / result["seconds"] for n in result["per_client"]]
            fan_out = {"clients": result["registered"], "min_per_second": min(rates),
                       "mean_per_second": sum(rates) / len(rates)}
    with _bare_modbus() as port:
        theirs = _modbus_figures(_run_load("modbus", str(port), str(args.modbus_clients),
                                           str(args.seconds), timeout=args.seconds + 120))
    return {"serial": serial, "modbus": {"polynav": ours, "reference": theirs},
            "udp_fan_out": fan_out}


def _print(figures: dict[str, Any], args: argparse.Namespace) -> None:
    s = figures["serial"]
    print(f"galileo wires on {platform.machine()} ({args.seconds:g} s each, the robot at real "
          "time with walkers)")
    print(f"  serial (pty): {s['frames_per_second']:.2f} status frames/s (target 30), "
          f"off the 30 Hz beat p50 {s['jitter_p50_ms']:.2f} ms, p99 {s['jitter_p99_ms']:.2f} ms")
    m = figures["modbus"]
    ours, theirs = m["polynav"], m["reference"]
    ratio = ours["per_second"] / theirs["per_second"] if theirs["per_second"] else 0.0
    print(f"  modbus, {args.modbus_clients} clients reading the {REGISTERS} input registers:")
    print(f"    polynav   {ours['per_second']:8.0f} reads/s ({ratio:.2f}x)  p50 "
          f"{ours['p50_ms']:.2f} ms  p99 {ours['p99_ms']:.2f} ms  errors {ours['errors']}")
    print(f"    reference {theirs['per_second']:8.0f} reads/s  (bare pymodbus server, static "
          f"block)  p50 {theirs['p50_ms']:.2f} ms  p99 {theirs['p99_ms']:.2f} ms")
    u = figures["udp_fan_out"]
    if u is not None:
        print(f"  udp fast, /galileo/status to {u['clients']} clients: min "
              f"{u['min_per_second']:.1f}, mean {u['mean_per_second']:.1f} messages/s each "
              "(the topic's 10 Hz)")


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "--load":
        kind, rest = argv[1], argv[2:]
        if kind == "serial":
            result = _load_serial(rest[0], float(rest[1]))
        elif kind == "modbus":
            result = _load_modbus(int(rest[0]), int(rest[1]), float(rest[2]))
        else:
            result = _load_udp(int(rest[0]), int(rest[1]), float(rest[2]))
        print(json.dumps(result))
        return 0
    parser = argparse.ArgumentParser(prog="polynav bench api --dialect galileo-wire",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0, help="per load")
    parser.add_argument("--modbus-clients", type=int, default=20)
    parser.add_argument("--udp-clients", type=int, default=20, help="0: no UDP fan-out")
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    args = parser.parse_args(argv)
    if args.seconds <= 0 or args.modbus_clients < 1 or args.udp_clients < 0:
        parser.error("--seconds > 0, --modbus-clients >= 1, --udp-clients >= 0")
    figures = run(args)
    _print(figures, args)
    if args.json:
        print(json.dumps(figures))
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
    raise SystemExit(main())
