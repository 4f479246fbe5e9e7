"""Yunji wire format: URL-like commands in, one compact JSON object per line out.

Pure (no socket, clock or runtime). The spec leaves framing undefined (§1.3, §A-T1); this codec
follows the spec's suggested resolution:

* A command ends at ``\\n`` (a preceding ``\\r`` is dropped), or where the next command starts:
  a new ``/api/`` or ``http://`` token. Third-party clients send bare commands, one per
  ``send()``, with no terminator; :func:`decode` therefore takes ``end_of_read``: when the caller
  (the server) has drained what the socket had, the rest of the buffer is one whole command.
* A legacy ``http://host[:port]`` prefix is stripped (§A-T2).
* Parameters are ``name=value`` pairs joined by ``&``; names and values are percent-decoded as
  UTF-8 (``+`` stays a plus sign: values such as ``location=1,+2,0`` keep their meaning). A
  repeated name keeps its last value. A malformed ``%`` escape or invalid UTF-8 is an error.
* A buffer longer than ``max_bytes`` with no delimiter is :class:`FrameTooLong`: the server
  closes the connection, since it can no longer find where the next command starts.

Outgoing packets (§2.1–§2.4) are compact JSON followed by ``\\n``, which works for clients that
split on newlines and for clients that stream-decode concatenated JSON.
"""

from __future__ import annotations

import logging
import re
from dataclasses import dataclass
from urllib.parse import unquote_to_bytes

import orjson

from polynav.errors import InvalidRequest

log = logging.getLogger(__name__)

DEFAULT_MAX_COMMAND_BYTES = 4096

_API = b"/api/"
_HTTP = b"http://"
_BAD_ESCAPE = re.compile(r"%(?![0-9A-Fa-f]{2})")
_WHITESPACE = b" \t\r\n"


class MissingType:
    """The type of :data:`MISSING`: a reply without a ``results`` field (not ``null``)."""

    _instance: MissingType | None = None

    def __new__(cls) -> MissingType:
        if cls._instance is None:
            cls._instance = super().__new__(cls)
        return cls._instance

    def __repr__(self) -> str:
        return "MISSING"


MISSING = MissingType()


@dataclass(frozen=True, slots=True)
class Command:
    """One decoded command.

    Attributes:
        path: the bare path, e.g. ``/api/move`` (what replies echo as ``command``).
        params: decoded parameters, ``uuid`` included.
        raw: the command text as received (prefix and query string included, delimiter not).
    """

    path: str
    params: dict[str, str]
    raw: str

    @property
    def uuid(self) -> str:
        """The client's ``uuid`` parameter, ``""`` when absent (§1.2)."""
        return self.params.get("uuid", "")


class MalformedCommand(InvalidRequest):
    """A delimited command that cannot be parsed; the server answers it and reads on.

    Attributes:
        used: bytes of the buffer the bad command took (drop them and go on).
        path: the path, as far as it could be read (``""`` if not at all), to echo.
        uuid: the ``uuid`` parameter, if it could be read.
    """

    def __init__(
        self, field: str, reason: str, *, used: int, path: str = "", uuid: str = ""
    ) -> None:
        super().__init__(field, reason)
        self.used = used
        self.path = path
        self.uuid = uuid


class FrameTooLong(InvalidRequest):
    """No delimiter within ``max_bytes``: the stream cannot be resynchronized."""


def decode(
    buf: bytes, *, end_of_read: bool = False, max_bytes: int = DEFAULT_MAX_COMMAND_BYTES
) -> tuple[int, Command | None]:
    """Take the first command off ``buf``.

    Args:
        buf: bytes received and not yet used.
        end_of_read: the caller has nothing more to read now, so an undelimited rest of the
            buffer is a whole command (clients that send bare commands, one per ``send()``).
        max_bytes: the longest command accepted.

    Returns:
        ``(used, command)``: drop ``used`` bytes from the buffer. ``command`` is ``None`` when no
        whole command is there yet (``used`` may still be > 0: blank lines are skipped).

    Raises:
        MalformedCommand: a delimited command that cannot be parsed (``used`` says how far it
            went).
        FrameTooLong: more than ``max_bytes`` without a delimiter.
    """
    skip = len(buf) - len(buf.lstrip(_WHITESPACE))
    if skip == len(buf):
        return skip, None
    start = skip
    own = buf.find(_API, start)
    if buf.startswith(_HTTP, start) and own < 0:
        own = len(buf)  # a prefix whose /api/ has not arrived yet
    elif not buf.startswith(_HTTP, start):
        own = start
    end = _next_delimiter(buf, start, own)
    if end is None:
        if len(buf) - start > max_bytes:
            raise FrameTooLong("command", f"longer than {max_bytes} bytes without a delimiter")
        if not end_of_read:
            return skip, None
        end = len(buf)
    text_bytes = buf[start:end].rstrip(b"\r")
    used = end + 1 if end < len(buf) and buf[end : end + 1] == b"\n" else end
    if len(text_bytes) > max_bytes:
        raise MalformedCommand(
            "command", f"longer than {max_bytes} bytes", used=used
        )
    return used, _parse(text_bytes, used)


def _next_delimiter(buf: bytes, start: int, own: int) -> int | None:
    """Where the command starting at ``start`` ends: a newline or the next command's token."""
    candidates = [buf.find(b"\n", start)]
    search_from = max(own + 1, start + 1)
    candidates.append(buf.find(_API, search_from))
    candidates.append(buf.find(_HTTP, search_from))
    found = [c for c in candidates if c >= 0]
    return min(found) if found else None


def _parse(text_bytes: bytes, used: int) -> Command:
    try:
        raw = text_bytes.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise MalformedCommand("command", "not valid UTF-8", used=used) from exc
    target = raw
    if target.startswith("http://"):
        slash = target.find("/", len("http://"))
        target = target[slash:] if slash >= 0 else ""
    path, _, query = target.partition("?")
    if not path.startswith("/api/"):
        raise MalformedCommand(
            "command", f"a command starts with /api/, got {raw[:40]!r}", used=used
        )
    params: dict[str, str] = {}
    bad: tuple[str, str] | None = None
    for pair in query.split("&") if query else ():
        if not pair:
            continue
        name, _, value = pair.partition("=")
        try:
            key = _unquote(name)
            params[key] = _unquote(value)
        except ValueError as exc:
            bad = bad or (name, str(exc))
    if bad is not None:
        raise MalformedCommand(
            bad[0] or "query", bad[1], used=used, path=path, uuid=params.get("uuid", "")
        )
    return Command(path=path, params=params, raw=raw)


def _unquote(text: str) -> str:
    if _BAD_ESCAPE.search(text):
        raise ValueError(f"malformed percent-encoding in {text[:40]!r}")
    try:
        return unquote_to_bytes(text).decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"percent-encoding is not UTF-8 in {text[:40]!r}") from exc


def _dumps(obj: dict[str, object]) -> bytes:
    # orjson writes what json.dumps(separators=(",", ":"), ensure_ascii=False) writes, in UTF-8,
    # at a fifth of the cost (the encoding was a third of a status command's time on the wire).
    # A NaN or an infinity (never in a reply we build) becomes null, where json refused it.
    try:
        return orjson.dumps(obj, option=orjson.OPT_APPEND_NEWLINE)
    except orjson.JSONEncodeError as exc:
        raise ValueError(f"cannot encode a reply: {exc}") from exc


def encode_reply(
    command: str,
    uuid: str,
    status: str,
    error_message: str = "",
    results: object = MISSING,
    *,
    task_id: str | None = None,
) -> bytes:
    """A ``type: response`` packet (§2.1).

    Args:
        command: the bare path the client sent (§A-J3: always the bare path).
        uuid: the client's uuid, ``""`` when none.
        status: a :class:`~polynav.protocols.yunji.messages.Status` value.
        error_message: ``""`` on success.
        results: the interface's data; :data:`MISSING` leaves the field out (``None`` is
            ``null``, as ``query_list`` answers with no markers).
        task_id: only on a successful ``/api/move``.
    """
    packet: dict[str, object] = {
        "type": "response",
        "command": command,
        "uuid": uuid,
        "status": status,
        "error_message": error_message,
    }
    if not isinstance(results, MissingType):
        packet["results"] = results
    if task_id is not None:
        packet["task_id"] = task_id
    return _dumps(packet)


def encode_callback(topic: str, results: object) -> bytes:
    """A ``type: callback`` packet of a ``/api/request_data`` stream (§2.3)."""
    return _dumps({"type": "callback", "topic": topic, "results": results})


def encode_notification(
    code: str, level: str, description: str, data: dict[str, object] | None = None
) -> bytes:
    """A ``type: notification`` packet (§2.4); ``data`` is ``{}`` when there is none."""
    return _dumps(
        {
            "type": "notification",
            "code": code,
            "level": level,
            "description": description,
            "data": data if data is not None else {},
        }
    )
