"""The datagrams of Galileo's UDP fast protocol (galileo-wire-protocols §4): a pure codec.

Byte 0 of every datagram says what it is: ``0x01`` a connection frame (``01`` + UTF-8
``udp://host:port/path?token=...`` + ``00``), ``0x02`` a data frame (``02`` + 4-byte client id +
opcode + payload). As both example clients implement it (A8), only BINARY frames carry a
``package_index`` (uint32 little-endian, bytes 6-9) before their data; TEXT, PING, PONG and
CLOSE carry none. The connection reply is a TEXT data frame whose payload is the JSON
``{"status": bool, "client_id": [4 bytes]}``: the clients skip its first 6 bytes (A9).

Messages, both ways, are JSON text. One that fits a datagram of :data:`MAX_DATAGRAM` bytes goes
as one TEXT frame; a longer one (``/scan``, ``/map``) goes as BINARY frames of :data:`CHUNK`
bytes with consecutive package indices, the last one shorter than :data:`CHUNK` (empty when the
text is a multiple of it), as TFTP ends a transfer. :class:`Reassembler` joins them again.

No I/O here: the server (:mod:`~polynav.protocols.galileo.udp_fast`) and the tests' client use
the same few functions.
"""

from __future__ import annotations

import json
import struct
from dataclasses import dataclass
from enum import IntEnum
from urllib.parse import parse_qs, urlsplit

CONNECT = 0x01  # byte 0 of a connection frame
DATA = 0x02  # byte 0 of a data frame
ID_SIZE = 4
HEADER_SIZE = 1 + ID_SIZE + 1  # marker, client id, opcode
INDEX_SIZE = 4
#: The largest datagram either side sends or takes (§4.2).
MAX_DATAGRAM = 1024
#: Data bytes per BINARY frame, as the example clients split (§4.5).
CHUNK = 512
#: The longest message a client may send as BINARY chunks (a command is a few hundred bytes).
MAX_INBOUND_MESSAGE = 65_536

_INDEX = struct.Struct("<I")


class Opcode(IntEnum):
    """Byte 5 of a data frame (§4.3)."""

    CONTINUATION = 0x00
    TEXT = 0x01
    BINARY = 0x02
    CLOSE = 0x08
    PING = 0x09
    PONG = 0x0A


class BadConnectFrame(ValueError):
    """A connection frame that names no topic as §4.4 says (the reason is the message)."""


@dataclass(frozen=True, slots=True)
class Registration:
    """What a connection frame asks for: the topic ``path`` (a leading ``/`` added, A27) and
    the ``token`` (``None``: none)."""

    path: str
    token: str | None


@dataclass(frozen=True, slots=True)
class DataFrame:
    """A data frame: ``payload`` is the data after the header (after the package index for
    BINARY, whose index is ``package_index``)."""

    client_id: bytes
    opcode: int
    payload: bytes
    package_index: int | None = None


def parse_connect(datagram: bytes) -> Registration:
    """The registration a connection frame asks for.

    Raises:
        BadConnectFrame: not ``01`` + ``udp://`` URL + ``00``, or no topic in the URL.
    """
    if not datagram or datagram[0] != CONNECT:
        raise BadConnectFrame("a connection frame starts with 0x01")
    if len(datagram) > MAX_DATAGRAM:
        raise BadConnectFrame(f"a connection frame has at most {MAX_DATAGRAM} bytes")
    end = datagram.find(b"\x00", 1)
    if end < 0:
        raise BadConnectFrame("a connection frame ends with 0x00")
    try:
        url = datagram[1:end].decode("utf-8")
    except UnicodeDecodeError:
        raise BadConnectFrame("the connection URL is not UTF-8") from None
    if not url.lower().startswith("udp://"):
        raise BadConnectFrame("the connection URL is udp://host:port/topic?token=...")
    try:
        parts = urlsplit(url)
    except ValueError as exc:
        raise BadConnectFrame(f"bad connection URL: {exc}") from None
    path = "/" + parts.path.lstrip("/")
    if path == "/":
        raise BadConnectFrame("the connection URL names no topic")
    tokens = parse_qs(parts.query, keep_blank_values=True).get("token")
    return Registration(path=path, token=tokens[0] if tokens else None)


def parse_data(datagram: bytes) -> DataFrame | None:
    """A data frame, or ``None`` for what is none (wrong marker, truncated, oversized): the
    protocol has no error reply for those, so they are dropped."""
    if len(datagram) < HEADER_SIZE or len(datagram) > MAX_DATAGRAM or datagram[0] != DATA:
        return None
    client_id = bytes(datagram[1:5])
    opcode = datagram[5]
    if opcode == Opcode.BINARY:
        if len(datagram) < HEADER_SIZE + INDEX_SIZE:
            return None
        (index,) = _INDEX.unpack_from(datagram, HEADER_SIZE)
        return DataFrame(client_id, opcode, bytes(datagram[HEADER_SIZE + INDEX_SIZE:]), index)
    return DataFrame(client_id, opcode, bytes(datagram[HEADER_SIZE:]))


def header(client_id: bytes, opcode: Opcode) -> bytes:
    """``02 id opcode``: alone, a PING, PONG or CLOSE frame."""
    return bytes((DATA,)) + client_id + bytes((opcode,))


def connect_reply(client_id: bytes | None, description: str | None = None) -> bytes:
    """The answer to a connection frame: ``status`` true with the id, or false (``client_id``
    empty, the reason in ``description``, which the clients ignore) when ``client_id`` is
    ``None``."""
    body: dict[str, object] = {"status": client_id is not None,
                               "client_id": list(client_id or b"")}
    if description is not None:
        body["description"] = description
    return header(client_id or bytes(ID_SIZE), Opcode.TEXT) + json.dumps(body).encode()


class PackageCounter:
    """One client's ``package_index``: 0 first, +1 per BINARY frame, wrapping as a uint32."""

    def __init__(self, start: int = 0) -> None:
        self._next = start & 0xFFFFFFFF

    def take(self) -> int:
        index = self._next
        self._next = (index + 1) & 0xFFFFFFFF
        return index


def message_frames(client_id: bytes, text: str, counter: PackageCounter) -> tuple[bytes, ...]:
    """The datagrams carrying one message: a TEXT frame when it fits, else BINARY chunks."""
    data = text.encode("utf-8")
    if HEADER_SIZE + len(data) <= MAX_DATAGRAM:
        return (header(client_id, Opcode.TEXT) + data,)
    binary = header(client_id, Opcode.BINARY)
    frames = [binary + _INDEX.pack(counter.take()) + data[start:start + CHUNK]
              for start in range(0, len(data), CHUNK)]
    if len(data) % CHUNK == 0:
        frames.append(binary + _INDEX.pack(counter.take()))
    return tuple(frames)


class MessageTooLong(ValueError):
    """The chunks of one message passed :data:`MAX_INBOUND_MESSAGE` bytes."""


class Reassembler:
    """Joins BINARY chunks into messages: consecutive package indices, ended by a chunk shorter
    than :data:`CHUNK`. A gap (a datagram lost or reordered) drops the message it broke, up to
    that message's short last chunk; the chunk after that starts a new one.

    Args:
        limit: the longest message; past it the message is dropped and
            :class:`MessageTooLong` raised once.
    """

    def __init__(self, limit: int = MAX_INBOUND_MESSAGE) -> None:
        self._limit = limit
        self._parts: list[bytes] = []
        self._size = 0
        self._next: int | None = None
        self._discarding = False

    def feed(self, index: int, chunk: bytes) -> bytes | None:
        """The message this chunk completes, or ``None`` while it is incomplete.

        Raises:
            MessageTooLong: the message grew past the limit (its remaining chunks are ignored).
        """
        last = len(chunk) < CHUNK
        if self._next is not None and index != self._next:
            # A chunk is missing: what came before and what follows up to the message's end
            # are parts of a message that cannot be whole.
            self._reset()
            self._discarding = True
        self._next = (index + 1) & 0xFFFFFFFF
        if self._discarding:
            if last:
                self._reset()
            return None
        self._parts.append(chunk)
        self._size += len(chunk)
        if self._size > self._limit:
            self._reset()
            self._discarding = not last
            raise MessageTooLong(f"a message has at most {self._limit} bytes")
        if not last:
            return None
        message = b"".join(self._parts)
        self._reset()
        return message

    def _reset(self) -> None:
        self._parts.clear()
        self._size = 0
        self._discarding = False
