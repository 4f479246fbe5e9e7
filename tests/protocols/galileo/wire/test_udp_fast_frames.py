"""The UDP fast codec against the bytes of spec §4 (the derived examples of §4.4-§4.5), and the
chunking rule of long messages both ways (docs/decisions.md, "Galileo UDP fast protocol")."""

from __future__ import annotations

import json
import struct

import pytest

from polynav.protocols.galileo.udp_fast_frames import (
    CHUNK,
    MAX_DATAGRAM,
    BadConnectFrame,
    DataFrame,
    MessageTooLong,
    Opcode,
    PackageCounter,
    Reassembler,
    connect_reply,
    header,
    message_frames,
    parse_connect,
    parse_data,
)

ID = bytes((0, 0, 0, 1))


def test_the_spec_examples() -> None:
    frame = b"\x01udp://192.168.0.132:3547/cmd_vel?token=28b1c500400611ebb805493c9303c705\x00"
    assert len(frame) == 73
    registration = parse_connect(frame)
    assert (registration.path, registration.token) == ("/cmd_vel",
                                                       "28b1c500400611ebb805493c9303c705")
    assert parse_connect(b"\x01udp://h:3547/galileo/status?token=\x00").token == ""
    assert parse_connect(b"\x01udp://h:3547/galileo/status\x00").token is None
    reply = connect_reply(ID)
    assert reply[:6] == bytes.fromhex("020000000101")
    assert json.loads(reply[6:]) == {"status": True, "client_id": [0, 0, 0, 1]}
    assert header(ID, Opcode.PING) == bytes.fromhex("020000000109")
    assert parse_data(bytes.fromhex("02000000010200000000AABB")) == DataFrame(
        ID, Opcode.BINARY, b"\xaa\xbb", 0)
    assert parse_data(b"\x02\x00\x00\x00\x01\x01{\"linear\"}") == DataFrame(
        ID, Opcode.TEXT, b'{"linear"}')


@pytest.mark.parametrize("frame", [b"", b"\x02", b"\x01udp://h/x", b"\x01udp:/x\x00",
                                   b"\x01udp://h:1\x00", b"\x01\x80\x00",
                                   b"\x01udp://h:99999999999/x\x00" + b"x" * MAX_DATAGRAM])
def test_bad_connection_frames_raise(frame: bytes) -> None:
    with pytest.raises(BadConnectFrame):
        parse_connect(frame)


def test_truncated_and_oversized_data_frames_are_none() -> None:
    for datagram in (b"", b"\x02\x00\x00", b"\x02" + ID, b"\x02" + ID + b"\x02\x00\x00\x00",
                     b"\x01" + ID + b"\x09", b"\x02" + ID + b"\x01" + b"x" * MAX_DATAGRAM):
        assert parse_data(datagram) is None


@pytest.mark.parametrize("size", [0, 10, 1018, 1019, CHUNK * 3, CHUNK * 3 + 1, 100_000])
def test_messages_split_and_join(size: int) -> None:
    text = "x" * size
    counter = PackageCounter()
    frames = message_frames(ID, text, counter)
    assert all(len(f) <= MAX_DATAGRAM for f in frames)
    if size <= MAX_DATAGRAM - 6:
        assert frames == (header(ID, Opcode.TEXT) + text.encode(),)
        return
    parsed = [parse_data(f) for f in frames]
    assert all(p is not None and p.opcode == Opcode.BINARY for p in parsed)
    assert [p.package_index for p in parsed if p] == list(range(len(frames)))
    joiner = Reassembler(limit=1_000_000)
    results = [joiner.feed(p.package_index or 0, p.payload) for p in parsed if p]
    assert results[:-1] == [None] * (len(frames) - 1)
    assert results[-1] == text.encode()
    assert len(parsed[-1].payload if parsed[-1] else b"") < CHUNK  # the end: a short chunk


def test_a_gap_drops_the_broken_message_and_the_limit_holds() -> None:
    joiner = Reassembler(limit=3 * CHUNK)
    full = b"a" * CHUNK
    assert joiner.feed(7, full) is None
    assert joiner.feed(9, b"end") is None  # 8 lost: 7 + 9 is no message
    assert joiner.feed(10, full) is None
    assert joiner.feed(11, b"end") == full + b"end"
    with pytest.raises(MessageTooLong):
        for index in range(12, 20):
            joiner.feed(index, full)
    assert joiner.feed(20, full) is None  # the rest of the long one is skipped
    assert joiner.feed(21, b"") is None
    assert joiner.feed(22, b"next") == b"next"


def test_the_package_index_wraps_as_a_uint32() -> None:
    counter = PackageCounter(0xFFFFFFFF)
    frames = message_frames(ID, "y" * 1500, counter)
    indices = [struct.unpack_from("<I", f, 6)[0] for f in frames]
    assert indices == [0xFFFFFFFF, 0, 1]
    joiner = Reassembler()
    out = [joiner.feed(i, f[10:]) for i, f in zip(indices, frames, strict=True)]
    assert out[-1] == b"y" * 1500
