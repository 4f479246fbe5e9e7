"""WS /api/ws: the status snapshot at a requested rate and every runtime event as it happens.

Messages are ``{"type": "status", "data": <GET /api/status body>}`` and
``{"type": "event", "data": {"kind": ..., "stamp": ..., ...}}``. The rate is counted on the
robot's SIMULATED clock (the snapshot's ``stamp``), so at ``--speed 20`` a 5 Hz stream is 100
messages per wall second and a client sees the same stream at every speed. Each client has its
own event subscription: a slow client loses its oldest events (counted), never slows the robot.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any

from fastapi import APIRouter, Query, WebSocket, WebSocketDisconnect

from polynav.api.errors import error_body

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api", tags=["events"])


def event_message(event: Any) -> dict[str, Any]:
    """The WebSocket message of one runtime event."""
    data = dict(event.to_dict())
    data.setdefault("kind", event.kind)
    data.setdefault("stamp", event.stamp)
    return {"type": "event", "data": data}


class StatusPacer:
    """Decides when the next status message is due, on simulated time.

    Due at the first snapshot, then every ``1 / rate`` simulated seconds; after a stall (a paused
    clock or a slow client) it restarts from the present instead of bursting to catch up.
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
            self._next = nxt if nxt > stamp + self._EPS else stamp + self.period
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
    subscription = runtime.bus.subscribe()
    pacer = StatusPacer(hz)
    closed = asyncio.Event()
    watcher = asyncio.create_task(_watch_disconnect(websocket, closed))
    last_stamp: float | None = None
    try:
        while not closed.is_set():
            for event in subscription.get_nowait():
                await websocket.send_json(event_message(event))
            snapshot = runtime.status()
            if snapshot.stamp != last_stamp and pacer.due(snapshot.stamp):
                last_stamp = snapshot.stamp
                await websocket.send_json({"type": "status", "data": snapshot.to_dict()})
            try:
                await asyncio.wait_for(closed.wait(), timeout=config.ws_poll_interval)
            except asyncio.TimeoutError:
                pass
    except (WebSocketDisconnect, RuntimeError) as exc:
        log.debug("websocket client left: %s", exc)
    finally:
        watcher.cancel()
        runtime.bus.unsubscribe(subscription)
        dropped = getattr(subscription, "dropped", 0)
        if dropped:
            log.warning("websocket client was too slow: %d events dropped", dropped)
