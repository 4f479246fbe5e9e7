"""Galileo API benchmark: ``GET /api/v1/system/galileo_status`` under concurrent keep-alive
clients, polynav beside a bare server answering the same JSON.

polynav runs as ``polynav run`` serves it (the simulated robot at real time, walkers on, the
Galileo HTTP server on its own event-loop thread); the client load comes from a separate process
(``api_load.py get``), so the clients never share the server's GIL. The reference is a bare
uvicorn + Starlette app answering the GalileoStatus body polynav gave, with nothing behind it.
Run ``polynav bench api --dialect galileo [--http-clients 50] [--seconds 5] [--json]``.
"""

from __future__ import annotations

import argparse
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

from api import _figures, _get_json, _load, _Uvicorn  # noqa: E402  (a sibling script)

PATH = "/api/v1/system/galileo_status"


@contextmanager
def _polynav() -> Iterator[int]:
    """polynav's Galileo HTTP port, the robot running."""
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
        galileo = GalileoThread(runtime, GalileoConfig(port=0, ws_port=None, announce=False))
        try:
            yield galileo.port
        finally:
            galileo.stop()
            runtime.stop()


def _bare(status: dict[str, Any]) -> Starlette:
    async def get_status(request: Request) -> Response:
        return JSONResponse(status)

    return Starlette(routes=[Route(PATH, get_status)])


def run(args: argparse.Namespace) -> dict[str, Any]:
    extra = ("--path", PATH)
    with _polynav() as port:
        status = _get_json(port, PATH)
        ours = _figures(_load("get", port, args.http_clients, args.seconds, *extra))
    reference = _Uvicorn(_bare(status))
    try:
        theirs = _figures(_load("get", reference.port, args.http_clients, args.seconds, *extra))
    finally:
        reference.close()
    return {"polynav": ours, "reference": theirs, "body_bytes": len(json.dumps(status))}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="polynav bench api --dialect galileo",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--http-clients", type=int, default=50, help="keep-alive connections")
    parser.add_argument("--seconds", type=float, default=5.0, help="per load")
    parser.add_argument("--json", action="store_true", help="end with one JSON line of figures")
    args = parser.parse_args(argv)
    if args.http_clients < 1 or not args.seconds > 0.0:
        parser.error("--http-clients must be >= 1 and --seconds > 0")
    figures = run(args)
    ours, theirs = figures["polynav"], figures["reference"]
    print(f"polynav bench api --dialect galileo: GET {PATH}, {args.http_clients} keep-alive "
          f"clients, {args.seconds:g} s each; Python {platform.python_version()}")
    print("reference: bare uvicorn + Starlette answering the same JSON")
    print(f"{'':14s}{'requests/s':>12s}{'p50 ms':>9s}{'p99 ms':>9s}{'errors':>8s}")
    for label, row in (("polynav", ours), ("reference", theirs)):
        print(f"{label:14s}{row['per_second']:12.0f}{row['p50_ms']:9.2f}{row['p99_ms']:9.2f}"
              f"{row['errors']:8d}")
    if args.json:
        print(json.dumps({"http_clients": args.http_clients, "seconds": args.seconds,
                          **figures}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
