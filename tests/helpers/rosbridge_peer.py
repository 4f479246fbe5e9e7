"""A small rosbridge v2 peer written from the protocol alone (not polynav's server), standing
for a robot's rosbridge_server: it takes subscribe, advertise, publish and call_service, records
what clients publish, and sends the messages a test gives it to their subscribers."""

from __future__ import annotations

import asyncio
import json
import threading
from collections import defaultdict
from typing import Any

from websockets.asyncio.server import Server, ServerConnection, serve
from websockets.exceptions import ConnectionClosed

from tests.helpers.loop_thread import LoopThread


class RosbridgePeer:
    """Serve on 127.0.0.1:``port`` (0: any) until :meth:`stop`; :meth:`start` again reuses
    the same port."""

    def __init__(self, port: int = 0) -> None:
        self.port = port
        self.loop = LoopThread()
        self.published: dict[str, list[dict[str, Any]]] = defaultdict(list)
        self.subscribed: dict[str, str] = {}  # topic -> type asked for
        self.advertised: dict[str, str] = {}
        self.connections = 0
        self._clients: set[ServerConnection] = set()
        self._subs: dict[ServerConnection, set[str]] = defaultdict(set)
        self._server: Server | None = None
        self.changed = threading.Condition()

    def start(self) -> None:
        async def start() -> None:
            self._server = await serve(self._serve, "127.0.0.1", self.port)
            self.port = self._server.sockets[0].getsockname()[1]

        self.loop.run(start())

    def stop(self) -> None:
        async def stop() -> None:
            if self._server is not None:
                self._server.close()
                await self._server.wait_closed()
                self._server = None

        self.loop.run(stop())

    def close(self) -> None:
        self.stop()
        self.loop.close()

    def send(self, topic: str, msg: dict[str, Any]) -> int:
        """Publish ``msg`` to the clients that subscribe to ``topic``; how many got it."""
        async def send() -> int:
            frame = json.dumps({"op": "publish", "topic": topic, "msg": msg})
            sent = 0
            for ws, topics in list(self._subs.items()):
                if topic in topics:
                    try:
                        await ws.send(frame)
                        sent += 1
                    except ConnectionClosed:
                        pass
            return sent

        return self.loop.run(send())

    def send_raw(self, text: str) -> None:
        async def send() -> None:
            for ws in list(self._clients):
                await ws.send(text)

        self.loop.run(send())

    def wait(self, predicate: Any, timeout: float = 10.0) -> bool:
        with self.changed:
            return self.changed.wait_for(predicate, timeout)

    async def _serve(self, ws: ServerConnection) -> None:
        self._clients.add(ws)
        with self.changed:
            self.connections += 1
            self.changed.notify_all()
        try:
            async for frame in ws:
                data = json.loads(frame)
                op = data.get("op")
                with self.changed:
                    if op == "subscribe":
                        self.subscribed[data["topic"]] = data.get("type", "")
                        self._subs[ws].add(data["topic"])
                    elif op == "advertise":
                        self.advertised[data["topic"]] = data["type"]
                    elif op == "publish":
                        self.published[data["topic"]].append(data["msg"])
                    self.changed.notify_all()
                if op == "call_service":
                    values: Any = {"time": {"secs": 1, "nsecs": 0}}
                    result = data["service"] == "/rosapi/get_time"
                    await ws.send(json.dumps({"op": "service_response", "id": data.get("id"),
                                              "service": data["service"], "result": result,
                                              "values": values if result else "no such service"}))
        except ConnectionClosed:
            pass
        finally:
            self._clients.discard(ws)
            self._subs.pop(ws, None)
            await asyncio.sleep(0)
