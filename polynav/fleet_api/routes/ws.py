"""``WS /api/ws``: the robots' states and the fleet's events, pushed.

On connect, and every ``robots_period``, a ``{"type": "robots", "robots": [...]}`` message
(each as ``GET /api/robots`` gives it); each fleet event (a mission queued, dispatched,
started, done, failed, requeued, cancelled; a robot's connection) as
``{"type": "event", "seq", "at", "kind", "detail"}`` as it happens. ``?after=N`` also sends
the events kept after number N (a client that reconnects misses none still kept). The server
reads nothing from the client but its close.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any

from fastapi import APIRouter, Query, WebSocket, WebSocketDisconnect
from starlette.concurrency import run_in_threadpool

from polynav.fleet_api.deps import WsManagerDep
from polynav.fleet_api.schemas import RobotOut, event_json

log = logging.getLogger(__name__)

router = APIRouter(tags=["stream"])

POLL = 0.1
"""How often [s of wall time] the stream looks for new events."""


@router.websocket("/api/ws")
async def fleet_stream(websocket: WebSocket, manager: WsManagerDep,
                       after: int | None = Query(default=None, ge=0)) -> None:
    await websocket.accept()
    period: float = websocket.app.state.robots_period
    closed = asyncio.Event()

    async def watch_close() -> None:
        try:
            while (await websocket.receive())["type"] != "websocket.disconnect":
                pass  # the stream takes no requests: what a client sends is ignored
        finally:
            closed.set()

    watcher = asyncio.create_task(watch_close())
    seq = after if after is not None else _latest(manager.events_after(0))
    loop = asyncio.get_running_loop()
    next_robots = loop.time()
    try:
        while not closed.is_set():
            if loop.time() >= next_robots:
                views = await run_in_threadpool(manager.robots)
                robots: list[dict[str, Any]] = [
                    RobotOut.from_domain(v).model_dump(mode="json") for v in views]
                await websocket.send_json({"type": "robots", "robots": robots})
                next_robots = loop.time() + period
            for event in await run_in_threadpool(manager.events_after, seq):
                await websocket.send_json(event_json(event))
                seq = event.seq
            try:
                await asyncio.wait_for(closed.wait(), POLL)
            except TimeoutError:
                pass
    except (WebSocketDisconnect, RuntimeError) as exc:
        log.debug("fleet stream closed: %s", exc)
    finally:
        watcher.cancel()


def _latest(events: list[Any]) -> int:
    return int(events[-1].seq) if events else 0
