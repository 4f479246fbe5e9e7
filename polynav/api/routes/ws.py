"""WS /api/ws: the status snapshot at a requested rate and every runtime event as it happens.

Messages are ``{"type": "status", "data": <GET /api/status body>}``,
``{"type": "event", "data": {"kind": ..., "stamp": ..., ...}}`` and, while mapping, the live
map every ``1 / ws_map_rate`` simulated seconds: ``{"type": "map", "data": {"resolution",
"width", "height", "origin", "png"}}`` (``png``: the ROS picture, base64). The rates are
counted on the robot's SIMULATED clock (the snapshot's ``stamp``), so at ``--speed 20`` a 5 Hz
stream is 100 messages per wall second and a client sees the same stream at every speed.

A slow client never slows the robot, and costs a bounded amount: each client writes through an
:class:`~polynav.protocols.outbox.Outbox` whose unsent status messages are coalesced to the newest;
events are never dropped silently: a client that falls ``ws_queue_size`` events behind is closed
with code 1008 and the reason, and can reconnect.
"""

from __future__ import annotations

import asyncio
import base64
import contextlib
import json
import logging
from typing import Any

from fastapi import APIRouter, Query, WebSocket, WebSocketDisconnect

from polynav.api.errors import error_body
from polynav.errors import PolynavError
from polynav.maps.map import Map
from polynav.maps.ros_map import png_bytes
from polynav.protocols.outbox import Outbox, OutboxClosed

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api", tags=["events"])


def map_message(grid: Map) -> dict[str, Any]:
    """The WebSocket message of the live map."""
    info = grid.info
    return {"type": "map", "data": {
        "resolution": info.resolution, "width": info.width, "height": info.height,
        "origin": {"x": info.origin.x, "y": info.origin.y, "theta": info.origin.theta},
        "png": base64.b64encode(png_bytes(grid)).decode("ascii"),
    }}


def event_message(event: Any) -> dict[str, Any]:
    """The WebSocket message of one runtime event."""
    data = dict(event.to_dict())
    data.setdefault("kind", event.kind)
    data.setdefault("stamp", event.stamp)
    return {"type": "event", "data": data}


class StatusPacer:
    """Decides when the next status message is due, on simulated time.

    Due at the first snapshot, then every ``1 / rate`` simulated seconds; a message sent late
    keeps the schedule while the next one stays at least half a period after it, and after a
    longer stall (a paused clock, a slow client, a busy machine) the schedule restarts from the
    present instead of bursting to catch up.
    """

    def __init__(self, rate: float) -> None:
        self.period = 1.0 / rate
        self._next: float | None = None

    # Stamps are sums of tick periods: compare with a tolerance so 0.2 + 0.2 + 0.2 counts as 0.6.
    _EPS = 1e-6

    def due(self, stamp: float) -> bool:
        """Whether a status with this stamp should be sent (and count it if so)."""
        if self._next is None or stamp >= self._next - self._EPS:
            nxt = (self._next if self._next is not None else stamp) + self.period
            keep = nxt >= stamp + self.period / 2 - self._EPS
            self._next = nxt if keep else stamp + self.period
            return True
        return False


async def _watch_disconnect(websocket: WebSocket, closed: asyncio.Event) -> None:
    try:
        while True:
            message = await websocket.receive()
            if message["type"] == "websocket.disconnect":
                break
    except (WebSocketDisconnect, RuntimeError):
        pass
    closed.set()


CLOSE_TOO_SLOW = 1008  # policy violation: the client does not read fast enough
_CLOSE_TIMEOUT = 1.0  # [s wall] for the close frame to a client that may not read at all


def _text(message: dict[str, Any]) -> str:
    # As Starlette's send_json writes it.
    return json.dumps(message, separators=(",", ":"), ensure_ascii=False)


async def _write(websocket: WebSocket, outbox: Outbox[str]) -> None:
    with contextlib.suppress(OutboxClosed):
        while True:
            await websocket.send_text(await outbox.get())


@router.websocket("/ws")
async def stream(
    websocket: WebSocket,
    rate: float | None = Query(default=None, description="status messages per simulated second"),
) -> None:
    """Stream status and events until the client goes away."""
    state = websocket.app.state
    config = state.api_config
    await websocket.accept()
    hz = config.ws_default_rate if rate is None else rate
    if not 0.0 < hz <= config.ws_max_rate:
        await websocket.send_json(
            error_body("validation_error", f"rate: must be in (0, {config.ws_max_rate}]")
        )
        await websocket.close(code=1008)
        return
    runtime = state.runtime
    subscription = runtime.bus.subscribe(maxlen=config.ws_queue_size)
    outbox: Outbox[str] = Outbox(limit=config.ws_queue_size)
    pacer = StatusPacer(hz)
    map_pacer = StatusPacer(config.ws_map_rate)
    closed = asyncio.Event()
    watcher = asyncio.create_task(_watch_disconnect(websocket, closed))
    writer = asyncio.create_task(_write(websocket, outbox))
    last_stamp: float | None = None
    try:
        while not closed.is_set() and not outbox.closed and not writer.done():
            for event in subscription.get_nowait():
                outbox.event(_text(event_message(event)))
            if subscription.dropped:
                outbox.close(f"not reading: {subscription.dropped} events could not be queued")
                break
            snapshot = runtime.status()
            if snapshot.stamp != last_stamp and pacer.due(snapshot.stamp):
                last_stamp = snapshot.stamp
                outbox.status(_text({"type": "status", "data": snapshot.to_dict()}), "status")
            if snapshot.mode == "mapping" and map_pacer.due(snapshot.stamp):
                with contextlib.suppress(PolynavError):  # mapping ended meanwhile
                    grid = await asyncio.to_thread(runtime.mapping_map)
                    outbox.status(_text(map_message(grid)), "map")
            with contextlib.suppress(asyncio.TimeoutError):
                await asyncio.wait_for(closed.wait(), timeout=config.ws_poll_interval)
        if outbox.closed and not closed.is_set():
            reason = str(outbox.closed_reason)
            log.warning("websocket client too slow, closing: %s", reason)
            writer.cancel()
            with contextlib.suppress(asyncio.TimeoutError, WebSocketDisconnect, RuntimeError):
                await asyncio.wait_for(
                    websocket.close(code=CLOSE_TOO_SLOW, reason=reason[:120]), _CLOSE_TIMEOUT
                )
    except (WebSocketDisconnect, RuntimeError) as exc:
        log.debug("websocket client left: %s", exc)
    finally:
        writer.cancel()
        watcher.cancel()
        runtime.bus.unsubscribe(subscription)
