"""The legacy HTTP form of the Yunji API (§A-T2): ``GET http://robot:8808/api/...?...``.

Old Yunji clients send the same command strings as HTTP GET requests. Each request is parsed
by the same codec and answered by the same handlers as on the TCP port, and the body is the
same one JSON object (``application/json``, HTTP 200 whatever the Yunji ``status``: the status is
in the body, as on TCP). What HTTP cannot carry is refused: ``request_data`` streams need the
TCP connection (``REQUEST_DENIED``), and notifications go to TCP clients only. Other methods
are 405; requests the HTTP parser rejects (oversized request lines or headers) never reach a
handler. Served by uvicorn on the Yunji server's event loop.
"""

from __future__ import annotations

import logging
from collections.abc import Awaitable, Callable

from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import Response
from starlette.routing import Route

from polynav.protocols.yunji import codec
from polynav.protocols.yunji.messages import Reply, Status

log = logging.getLogger(__name__)

Answer = Callable[[codec.Command], Awaitable[tuple[bytes, Reply]]]
STREAMS_NEED_TCP = "request_data streams need the TCP connection (port 31001): HTTP cannot stream"


def create_app(answer: Answer, max_command_bytes: int) -> Starlette:
    """An ASGI app answering Yunji commands sent as ``GET`` paths with ``answer``."""

    async def command(request: Request) -> Response:
        target = request.url.path
        if request.url.query:
            target += "?" + request.url.query
        try:
            _, parsed = codec.decode(
                target.encode("utf-8"), end_of_read=True, max_bytes=max_command_bytes
            )
        except codec.MalformedCommand as exc:
            return _json(codec.encode_reply(exc.path, exc.uuid, Status.INVALID_REQUEST.value,
                                            str(exc)))
        except codec.FrameTooLong as exc:
            return _json(codec.encode_reply("", "", Status.INVALID_REQUEST.value, str(exc)))
        assert parsed is not None
        if parsed.path == "/api/request_data":
            return _json(codec.encode_reply(
                parsed.path, parsed.uuid, Status.REQUEST_DENIED.value, STREAMS_NEED_TCP
            ))
        packet, _ = await answer(parsed)
        return _json(packet)

    return Starlette(routes=[Route("/api/{rest:path}", command, methods=["GET"])])


def _json(packet: bytes) -> Response:
    return Response(packet, media_type="application/json")
