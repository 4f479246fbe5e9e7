"""The Puwei WebSocket (puwei-api §9): ``/api/ws?token=<token>`` on the HTTP port.

A client with a token the login gave out is accepted (any other is refused, close code 1008).
On connect it gets what a client opening the socket after ``task/set`` needs to catch up: the
map (O_MAP), the saved markers (O_MARKER) while navigating, an O_STATUS, and the running task's
state replayed as an O_EVENT (6 "开始执行任务", or 5 when paused), so a task's start is never lost
to a client that connects a moment after it. Then:

* O_STATUS at the runtime's status rate, counted on the runtime's clock (the stamps it carries);
* O_PATH whenever the running goal's plan changes;
* O_MAP again when navigation starts on a map, and every second of the runtime's clock while a
  map is being built; O_MARKER when navigation starts and when markers are saved;
* O_EVENT for every runtime event Puwei has an id for (:func:`.messages.events_for`), and for
  what the adapter does itself (10 goals received, 9 marker saved, 12 errors cleared);
* O_GOAL to the other clients when one sends I_GOAL.

A client message is checked whole first (:func:`.messages.parse`); an invalid one gets O_EVENT
1029 "输入的命令无效: <why>" to that client alone, and a command the robot refuses an O_EVENT
naming why (1025 for I_INIT, 1027 for I_MARKER, 2052 for I_CHARGE, 2049 for I_GOAL, else 1029);
the session stays open. A binary frame gets 1029 too, and so does a command that fails for a
reason polynav has no error class for (logged with its traceback). Runtime commands run on
worker threads (they wait for the runtime's loop), never on the adapter's event loop. Each
session's outgoing frames wait in a :class:`~polynav.protocols.outbox.Outbox`, as in the other
dialects: an unsent O_STATUS, O_PATH or O_MAP is replaced by the next one, and events, goals and
markers are never dropped silently (a client whose task-completion event would be lost is one that
waits for ever); a client that leaves ``OUTBOX`` of them unread is closed (1008, with the reason),
so the server keeps its memory. The session ends as soon as the client closes.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any, TypeVar

from starlette.websockets import WebSocket, WebSocketDisconnect

from polynav.errors import InvalidRequest, NotFound, PolynavError
from polynav.geometry import Pose2D
from polynav.maps import ros_map
from polynav.protocols.outbox import Outbox, OutboxClosed
from polynav.protocols.puwei import messages as m
from polynav.protocols.puwei.context import Context
from polynav.protocols.puwei.maps import site_store
from polynav.protocols.puwei.robot import clear_errors, robot_status, set_charging, set_paused
from polynav.runtime import events
from polynav.site import Point

log = logging.getLogger(__name__)

T = TypeVar("T")

OUTBOX = 256  # events waiting unsent for one client; one more closes it as not reading
CLOSE_TOO_SLOW = 1008  # policy violation: the client does not read
CLOSE_TIMEOUT = 1.0  # [s] of wall time for the close handshake with a client that does not read
TICK = 0.02  # [s] of wall time between looks at the runtime
LIVE_MAP_PERIOD = 1.0  # [s] of the runtime's clock between maps while mapping
GOALS_KIND = "puwei_goals"


@dataclass
class Hub:
    """The adapter's open sessions, for frames sent to every client (or all but one)."""

    sessions: set[Session] = field(default_factory=set)

    def broadcast(self, text: str, *, but: Session | None = None) -> None:
        for session in list(self.sessions):
            if session is not but:
                session.send(text)


def hub(ctx: Context) -> Hub:
    return ctx.state("ws_hub", Hub)


async def websocket_session(websocket: WebSocket, ctx: Context) -> None:
    """Serve one WebSocket client until it closes."""
    if not ctx.tokens.valid(websocket.query_params.get("token")):
        await websocket.close(code=1008, reason="no valid token: log in first")
        return
    await websocket.accept()
    session = Session(websocket, ctx)
    hub(ctx).sessions.add(session)
    try:
        await session.run()
    finally:
        hub(ctx).sessions.discard(session)


class Session:
    """One client."""

    def __init__(self, websocket: WebSocket, ctx: Context) -> None:
        self._ws = websocket
        self._ctx = ctx
        self._rt = ctx.runtime
        self._outbox: Outbox[str] = Outbox(limit=OUTBOX)
        self._task_states: dict[str, str] = {}
        self._path: list[tuple[float, float]] = []
        self._next_status = self._rt.now()
        self._next_map = self._rt.now()

    def send(self, text: str) -> None:
        """Queue an event-like frame for this client: never dropped; too many unsent close it."""
        self._outbox.event(text)

    def send_latest(self, text: str, key: str) -> None:
        """Queue a frame that the next one of the same ``key`` supersedes (status, path, map)."""
        self._outbox.status(text, key)

    async def run(self) -> None:
        subscription = self._rt.bus.subscribe(maxlen=1000)
        try:
            await self._greet()
            parts = [asyncio.create_task(self._read()), asyncio.create_task(self._write()),
                     asyncio.create_task(self._watch(subscription))]
            done, pending = await asyncio.wait(parts, return_when=asyncio.FIRST_COMPLETED)
            for part in pending:
                part.cancel()
            for part in pending:
                with contextlib.suppress(asyncio.CancelledError, WebSocketDisconnect):
                    await part
            for part in done:
                if not part.cancelled() and part.exception() is not None and not isinstance(
                        part.exception(), WebSocketDisconnect | RuntimeError):
                    log.error("puwei: WebSocket session failed", exc_info=part.exception())
            if self._outbox.closed:
                await self._close_slow()
        finally:
            self._rt.bus.unsubscribe(subscription)

    async def _close_slow(self) -> None:
        """Close a client that does not read; bounded, since its socket may be stuck too."""
        reason = str(self._outbox.closed_reason)
        log.warning("puwei: WebSocket client too slow, closing: %s", reason)
        with contextlib.suppress(TimeoutError, WebSocketDisconnect, RuntimeError):
            await asyncio.wait_for(self._ws.close(code=CLOSE_TOO_SLOW, reason=reason[:120]),
                                   CLOSE_TIMEOUT)

    async def _call(self, fn: Callable[[], T]) -> T:
        return await asyncio.to_thread(fn)

    # -- on connect ------------------------------------------------------------------------

    async def _greet(self) -> None:
        await self._send_map()
        if self._rt.status().mode == "navigating":
            await self._send_markers()
        self.send_latest(m.frame(m.Out.O_STATUS, robot_status(self._ctx)), "status")
        task = self._rt.tasks.running()
        if task is not None:
            self._task_states[task["id"]] = task["state"]
            self.send(m.event(m.TASK_PAUSED if task["state"] == "PAUSED" else m.TASK_STARTED))

    async def _send_map(self) -> None:
        rt = self._rt
        snap = rt.status()
        if snap.mode == "mapping":
            grid = await self._call(rt.mapping_map)
            info = grid.info
            png = await self._call(lambda: ros_map.png_bytes(grid))
            self.send_latest(m.frame(m.Out.O_MAP, m.map_data(png, info.resolution, info.width,
                                                             info.height, info.origin)), "map")
        elif snap.map is not None and snap.frame == "map":
            name = snap.map
            store = site_store(self._ctx)
            record = store.map_record(name)
            png = await self._call(lambda: store.map_image_path(name).read_bytes())
            self.send_latest(m.frame(m.Out.O_MAP, m.map_data(png, record.resolution,
                                                             record.width, record.height,
                                                             record.origin)), "map")

    async def _send_markers(self, *, everyone: bool = False) -> None:
        map_name = self._rt.status().map
        if map_name is None:
            return
        points = self._rt.store.points(map_name=map_name)
        text = m.frame(m.Out.O_MARKER, m.marker_data([(p.name, p.pose) for p in points]))
        if everyone:
            hub(self._ctx).broadcast(text)
        else:
            self.send(text)

    # -- the three parts -------------------------------------------------------------------

    async def _write(self) -> None:
        with contextlib.suppress(OutboxClosed):  # closed as not reading: run() closes
            while True:
                await self._ws.send_text(await self._outbox.get())

    async def _read(self) -> None:
        while True:
            # receive(), not receive_text(): Starlette's receive_text raises KeyError on a
            # binary frame, which would end the session over one bad frame.
            received = await self._ws.receive()
            if received["type"] == "websocket.disconnect":
                raise WebSocketDisconnect(received.get("code", 1000), received.get("reason"))
            text = received.get("text")
            if text is None:
                self.send(m.event(m.INVALID, "frame: must be JSON text, got a binary frame"))
                continue
            try:
                message = m.parse(text)
            except InvalidRequest as exc:
                self.send(m.event(m.INVALID, f"{exc.field}: {exc.reason}"))
                continue
            try:
                await self._handle(message)
            except PolynavError as exc:
                self.send(m.event(_REFUSED.get(message.kind, m.INVALID), str(exc)))
            except Exception:  # the session's one broad except (STYLE R4): keep the client
                log.error("puwei: WebSocket %s failed", message.kind.name, exc_info=True)
                self.send(m.event(m.INVALID, f"{message.kind.name}: internal error"))

    async def _watch(self, subscription: Any) -> None:
        rt = self._rt
        rate = rt.config.status_rate
        while not self._outbox.closed:  # a writer stuck on a client that does not read
            await asyncio.sleep(TICK)        # never sees the close: this part ends the session
            for happened in subscription.get_nowait():
                await self._forward(happened)
            if subscription.dropped:  # events lost before translation: say so, do not hide it
                self._outbox.close(f"not reading: {subscription.dropped} events could not be "
                                   "queued")
            # Counted on the stamp the status carries, not on the clock: a snapshot a tick
            # behind the clock, then one on time, were 60 ms apart in ``time_stamp`` at 10 Hz.
            snap = rt.status()
            if snap.stamp >= self._next_status:
                self._next_status = max(self._next_status + 1.0 / rate, snap.stamp)
                self.send_latest(m.frame(m.Out.O_STATUS, robot_status(self._ctx, snap)),
                                 "status")
                await self._check_path()
            now = rt.now()
            if snap.mode == "mapping" and now >= self._next_map:
                self._next_map = now + LIVE_MAP_PERIOD
                await self._send_map()

    async def _check_path(self) -> None:
        if self._rt.status().navigation_state != "running":
            self._path = []
            return
        path = await self._call(self._rt.queries.planned_path)
        if path and path != self._path:
            self._path = path
            self.send_latest(m.frame(m.Out.O_PATH, m.path_data(path)), "path")

    async def _forward(self, happened: events.RuntimeEvent) -> None:
        was_paused = False
        if isinstance(happened, events.TaskChanged) and happened.root:
            was_paused = self._task_states.get(happened.task_id) == "PAUSED"
            if self._task_states.get(happened.task_id) == happened.state:
                return  # replayed on connect already
            self._task_states[happened.task_id] = happened.state
            if len(self._task_states) > 1000:
                self._task_states.pop(next(iter(self._task_states)))
        for text in m.events_for(happened, was_paused=was_paused):
            self.send(text)
        if isinstance(happened, events.ModeChanged) and happened.new in ("navigating",
                                                                          "mapping"):
            await self._send_map()
            if happened.new == "navigating":
                await self._send_markers()

    # -- client messages -------------------------------------------------------------------

    async def _handle(self, message: m.Message) -> None:
        rt = self._rt
        kind = message.kind
        if kind is m.In.I_INIT:
            pose: Pose2D = message.data
            await self._call(lambda: rt.set_initial_pose(pose))
        elif kind is m.In.I_GOAL:
            poses, loop = message.data
            await self._call(lambda: self._start_goals(poses, loop))
            hub(self._ctx).broadcast(m.event(m.GOALS_RECEIVED))
            hub(self._ctx).broadcast(m.frame(m.Out.O_GOAL, m.goal_data(poses, loop)), but=self)
        elif kind is m.In.I_PAUSE:
            await self._call(lambda: set_paused(self._ctx, message.data))
        elif kind is m.In.I_CMD:
            linear, angular = message.data
            await self._call(lambda: rt.teleop(linear, angular))
        elif kind is m.In.I_CHARGE:
            await self._call(lambda: set_charging(self._ctx, message.data))
        elif kind is m.In.I_CLEAR:
            await self._call(lambda: clear_errors(self._ctx))
            hub(self._ctx).broadcast(m.event(m.CLEARED))
        elif kind is m.In.I_ALARM:
            await self._call(lambda: rt.peripherals.set_buzzer(message.data))
        elif kind is m.In.I_MARKER:
            await self._call(lambda: self._save_markers(message.data))
            hub(self._ctx).broadcast(m.event(m.MARKER_SAVED))
            await self._send_markers(everyone=True)

    def _start_goals(self, poses: tuple[Pose2D, ...], loop: int) -> None:
        """One task of the engine: the poses in order, ``loop`` rounds (0: for ever)."""
        if self._rt.status().mode != "navigating":
            raise InvalidRequest("I_GOAL", "start navigation first (roslaunch/navigation)")
        legs = [{"type": "nav_action", "x": p.x, "y": p.y, "theta": p.theta} for p in poses]
        self._rt.tasks.create({"name": "puwei goals", "control_type": "loop",
                               "target_loop_count": loop, "sub_tasks": legs},
                              owner="puwei", kind=GOALS_KIND, temporary=True, start=True)

    def _save_markers(self, markers: tuple[tuple[str, Pose2D], ...]) -> None:
        """Each marker a point of the map navigated on (a marker of that name is moved)."""
        store = site_store(self._ctx)
        map_name = self._rt.status().map
        if map_name is None or self._rt.status().mode != "navigating":
            raise InvalidRequest("I_MARKER", "markers are saved while navigating on a map")
        for name, pose in markers:
            try:
                old = store.point(map_name, name)
            except NotFound:
                store.add_point(Point(name, map_name, pose))
            else:
                store.update_point(map_name, name, replace(old, pose=pose))


#: The O_EVENT a refused command is answered with.
_REFUSED = {m.In.I_INIT: m.RELOC_FAILED, m.In.I_MARKER: m.MARKER_FAILED,
            m.In.I_CHARGE: m.DOCK_FAILED, m.In.I_GOAL: m.TASK_FAILED}
