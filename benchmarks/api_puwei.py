"""Puwei API benchmark: ``GET /api/robot/status`` under concurrent keep-alive clients with the
login's ``authorization`` header, polynav beside a bare server answering the same JSON.

polynav runs as ``polynav run`` serves it (the simulated robot at real time, walkers on, the
Puwei server on its own event-loop thread); the clients log in once and share the token, and the
load comes from a separate process (``api_load.py get``) so it never shares the server's GIL.
The reference is a bare uvicorn + Starlette app answering the envelope polynav gave, with
nothing behind it (it does not check the header). Run
``polynav bench api --dialect puwei [--http-clients 50] [--seconds 5] [--json]``.
"""

from __future__ import annotations

import argparse
import http.client
import json
import platform
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Route

sys.path.insert(0, str(Path(__file__).resolve().parent))

from api import _figures, _load, _Uvicorn  # noqa: E402  (a sibling script)

PATH = "/api/robot/status"


@contextmanager
def _polynav() -> Iterator[int]:
    """polynav's Puwei port, the robot running."""
    from polynav.protocols.puwei.config import PuweiConfig
    from polynav.protocols.puwei.server import PuweiThread
    from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
    from polynav.store.site_store import SiteStore
    from polynav.worlds import load_world

    world = load_world("demo")
    with tempfile.TemporaryDirectory() as tmp, SiteStore.open(
        Path(tmp) / "data", seed_world=world
    ) as store:
        runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=True))
        runtime.start()
        puwei = PuweiThread(runtime, PuweiConfig(port=0, discovery_port=None))
        try:
            yield puwei.port
        finally:
            puwei.stop()
            runtime.stop()


def _call(port: int, method: str, path: str, body: dict[str, Any] | None = None,
          token: str | None = None) -> tuple[dict[str, Any], str | None]:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    try:
        headers = {"Content-Type": "application/json"}
        if token is not None:
            headers["authorization"] = token
        connection.request(method, path, None if body is None else json.dumps(body), headers)
        answer = connection.getresponse()
        envelope: dict[str, Any] = json.loads(answer.read())
        return envelope, answer.getheader("authorization")
    finally:
        connection.close()


def _bare(envelope: dict[str, Any]) -> Starlette:
    async def get_status(request: Request) -> Response:
        return JSONResponse(envelope)

    return Starlette(routes=[Route(PATH, get_status)])


def run(args: argparse.Namespace) -> dict[str, Any]:
    with _polynav() as port:
        login, token = _call(port, "POST", "/api/user/login",
                             {"username": "admin", "password": "admin"})
        if login.get("code") != 0 or token is None:
            raise RuntimeError(f"the Puwei login failed: {login}")
        status, _ = _call(port, "GET", PATH, token=token)
        if status.get("code") != 0:
            raise RuntimeError(f"{PATH} failed: {status}")
        extra = ("--path", PATH, "--header", f"authorization: {token}")
        ours = _figures(_load("get", port, args.http_clients, args.seconds, *extra))
        stream = _load("ws", port, args.ws_clients, args.ws_seconds, "--path",
                       f"/api/ws?token={token}") if args.ws_clients else None
    reference = _Uvicorn(_bare(status))
    try:
        theirs = _figures(_load("get", reference.port, args.http_clients, args.seconds,
                                "--path", PATH))
    finally:
        reference.close()
    return {"polynav": ours, "reference": theirs, "body_bytes": len(json.dumps(status)),
            "o_status": stream}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="polynav bench api --dialect puwei",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--http-clients", type=int, default=50, help="keep-alive connections")
    parser.add_argument("--seconds", type=float, default=5.0, help="per load")
    parser.add_argument("--ws-clients", type=int, default=50,
                        help="WebSocket clients reading O_STATUS (0: none)")
    parser.add_argument("--ws-seconds", type=float, default=10.0)
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    args = parser.parse_args(argv)
    if args.http_clients < 1 or not args.seconds > 0.0 or args.ws_clients < 0 \
            or not args.ws_seconds > 0.0:
        parser.error("--http-clients must be >= 1, --ws-clients >= 0, the seconds > 0")
    figures = run(args)
    ours, theirs = figures["polynav"], figures["reference"]
    print(f"polynav bench api --dialect puwei: GET {PATH} with a token, {args.http_clients} "
          f"keep-alive clients, {args.seconds:g} s each; Python {platform.python_version()}")
    print("reference: bare uvicorn + Starlette answering the same JSON")
    print(f"{'':14s}{'requests/s':>12s}{'p50 ms':>9s}{'p99 ms':>9s}{'errors':>8s}")
    for label, row in (("polynav", ours), ("reference", theirs)):
        print(f"{label:14s}{row['per_second']:12.0f}{row['p50_ms']:9.2f}{row['p99_ms']:9.2f}"
              f"{row['errors']:8d}")
    ratio = ours["per_second"] / theirs["per_second"] if theirs["per_second"] else 0.0
    print(f"polynav / reference: {ratio:.2f}x (issue 33's target: >= 0.5x)")
    stream = figures["o_status"]
    if stream is not None:
        print(f"O_STATUS to {stream['subscribers']} WebSocket clients for {args.ws_seconds:g} s: "
              f"{stream['messages_per_second_min']:.1f} messages/s at the least (the status "
              f"rate: 10), lag growth {stream['lag_growth_ms']:+.1f} ms")
    if args.json:
        print(json.dumps({"http_clients": args.http_clients, "seconds": args.seconds,
                          **figures}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
