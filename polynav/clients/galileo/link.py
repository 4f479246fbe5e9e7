"""One connected robot: its HTTP API, its GalileoStatus stream, and the topics commands go to.

The Galileo WebSocket serves one topic per connection, so the link keeps three: it reads
``/galileo/status`` (in a thread that reconnects when the robot drops the connection) and
writes ``/galileo/cmds`` and ``/cmd_vel``. A status is kept as the robot sent it (the
GalileoStatus JSON); listeners are called on every one, from the reading thread.
"""

from __future__ import annotations

import contextlib
import json
import logging
import threading
import time
from collections.abc import Callable
from typing import Any

import httpx
from websockets.exceptions import WebSocketException
from websockets.sync.client import connect
from websockets.sync.connection import Connection

from polynav.clients.galileo.codes import ServerInfo
from polynav.protocols.galileo.native.ros_message import encode_native_cmds

log = logging.getLogger(__name__)

Status = dict[str, Any]
RECONNECT_PAUSE = 0.5  # [s] between attempts to read the status again


class LinkError(Exception):
    """The robot could not be reached (or refused the login)."""


class RobotLink:
    """HTTP and WebSocket connections to one robot.

    Args:
        server: the robot (address and HTTP port from its announcement).
        ws_port: its WebSocket port (3547 on a Galileo robot; the announcement does not say).
        username, password: the HTTP API's login (a robot that checks no token accepts any).
        on_status: called with each status.
        on_lost: called once when the status stream breaks (the link then retries).
    """

    def __init__(self, server: ServerInfo, ws_port: int, username: str, password: str,
                 on_status: Callable[[Status], None], on_lost: Callable[[], None]) -> None:
        self.server = server
        self._ws_base = f"ws://{server.ip}:{ws_port}"
        self.http = httpx.Client(base_url=f"http://{server.ip}:{server.port}", timeout=10.0)
        self._on_status = on_status
        self._on_lost = on_lost
        self._closed = threading.Event()
        self._send_lock = threading.Lock()
        # Typed as the base class: websockets 15 (amqtt's pin) types an entered client as it.
        self._writers: dict[str, Connection] = {}
        self._status_ws: Connection | None = None
        try:
            reply = self.http.get("/token", params={"username": username, "password": password})
            body = reply.json()
        except (httpx.HTTPError, ValueError) as exc:
            self.http.close()
            raise LinkError(f"no HTTP API at {server.ip}:{server.port}: {exc}") from exc
        if not body.get("result"):
            self.http.close()
            raise LinkError(f"login refused: {body.get('description', body)}")
        self.token: str = str(body["token"])
        self._reader = threading.Thread(target=self._read_status, name="galileo-sdk-status",
                                        daemon=True)
        self._reader.start()

    # -- HTTP ----------------------------------------------------------------------------------

    def request(self, method: str, url: str, body: str = "", timeout: float = 10.0
                ) -> httpx.Response:
        """``method`` on ``url`` (``/api/v1/...``) with the token added."""
        content = body.encode() if body else None
        headers = {"Content-Type": "application/json"} if body else None
        return self.http.request(method.upper(), url, params={"token": self.token},
                                 content=content, headers=headers, timeout=timeout)

    def call(self, path: str, body: dict[str, Any] | None = None, **params: Any) -> Any:
        """``GET /api/v1`` + ``path`` (``POST`` with a JSON ``body``); the JSON reply.

        Raises:
            LinkError: the robot did not answer 200.
        """
        query = {**params, "token": self.token}
        try:
            if body is None:
                reply = self.http.get("/api/v1" + path, params=query)
            else:
                reply = self.http.post("/api/v1" + path, params=query, json=body)
        except httpx.HTTPError as exc:
            raise LinkError(str(exc)) from exc
        if reply.status_code != 200:
            raise LinkError(f"{path}: HTTP {reply.status_code} {reply.text[:200]}")
        return reply.json()

    # -- topics --------------------------------------------------------------------------------

    def send_command(self, payload: bytes) -> None:
        """One native command on ``/galileo/cmds``."""
        self._publish("/galileo/cmds", encode_native_cmds(payload))

    def send_twist(self, linear: float, angular: float) -> None:
        zero = {"x": 0.0, "y": 0.0, "z": 0.0}
        self._publish("/cmd_vel", {"linear": {**zero, "x": float(linear)},
                                   "angular": {**zero, "z": float(angular)}})

    def ping(self) -> None:
        """A text ping on the status connection (the WebSocket's keep-alive)."""
        ws = self._status_ws
        if ws is None:
            raise LinkError("the status stream is not connected")
        try:
            ws.send("ping")
        except WebSocketException as exc:
            raise LinkError(str(exc)) from exc

    def _publish(self, topic: str, message: dict[str, Any]) -> None:
        text = json.dumps(message)
        with self._send_lock:
            for attempt in (1, 2):  # a dropped connection is opened again once
                ws = self._writers.get(topic)
                try:
                    if ws is None:
                        # entered as websockets >= 17.1 wants; closed in close()
                        ws = connect(self._url(topic), open_timeout=10).__enter__()
                        self._writers[topic] = ws
                    ws.send(text)
                    return
                except (OSError, WebSocketException) as exc:
                    self._writers.pop(topic, None)
                    if attempt == 2:
                        raise LinkError(f"{topic}: {exc}") from exc

    def _url(self, topic: str) -> str:
        return f"{self._ws_base}{topic}?token={self.token}"

    def _read_status(self) -> None:
        lost = False
        while not self._closed.is_set():
            try:
                with connect(self._url("/galileo/status"), open_timeout=10,
                             max_size=1 << 20) as ws:
                    self._status_ws = ws
                    lost = False
                    for text in ws:
                        message = json.loads(text)
                        if isinstance(message, dict) and "navStatus" in message:
                            self._on_status(message)
            except (OSError, WebSocketException, ValueError) as exc:
                log.debug("galileo sdk: status stream: %s", exc)
            self._status_ws = None
            if self._closed.is_set():
                return
            if not lost:
                lost = True
                self._on_lost()
            self._closed.wait(RECONNECT_PAUSE)

    def close(self) -> None:
        self._closed.set()
        with self._send_lock:
            for ws in self._writers.values():
                with contextlib.suppress(Exception):
                    ws.close()
            self._writers.clear()
        status_ws = self._status_ws
        if status_ws is not None:
            with contextlib.suppress(Exception):
                status_ws.close()
        self._reader.join(timeout=5.0)
        self.http.close()


def wait_until(done: Callable[[], bool], seconds: float, pause: float = 0.05) -> bool:
    """Poll ``done`` until true or ``seconds`` pass (wall time)."""
    deadline = time.monotonic() + seconds
    while not done():
        if time.monotonic() >= deadline:
            return False
        time.sleep(pause)
    return True
