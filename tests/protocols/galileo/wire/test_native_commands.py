"""The native command bytes and the status frame as bytes (galileo-wire-protocols §1.2-§1.4):
every command decoded and encoded, the worked frame of §1.3.2, and a reader that survives
garbage, split frames and bad length bytes."""

from __future__ import annotations

import struct

import pytest

from polynav.protocols.galileo.native import commands as c
from polynav.protocols.galileo.native.commands import (
    FrameReader,
    NativeCommand,
    UnknownCommand,
    encode_command,
    frame,
    parse_command,
)
from polynav.protocols.galileo.native.status_frame import (
    STATUS_FRAME_SIZE,
    pack_status,
    unpack_status,
)

# (bytes after the length byte, the command) for every command of §1.4.1
EVERY_COMMAND = [
    ("6D 00", NativeCommand("m 0")), ("6D 04", NativeCommand("m 4")),
    ("6D 09", NativeCommand("m 9")), ("67 03", NativeCommand("g", (3,))),
    ("69 00", NativeCommand("i 0")), ("69 01", NativeCommand("i 1")),
    ("69 02", NativeCommand("i 2")),
    ("67 69 00 00 80 3F 00 00 20 C0", NativeCommand("g i", (1.0, -2.5))),
    ("67 72 00", NativeCommand("g r 0")),
    ("66 32", NativeCommand("f", (50,))), ("62 64", NativeCommand("b", (100,))),
    ("63 0A", NativeCommand("c", (10,))), ("64 00", NativeCommand("d", (0,))),
    ("73 64", NativeCommand("s", (100,))), ("AA 44", NativeCommand("shutdown")),
    ("61 01 5A", NativeCommand("a", (1, 90))),
    ("6D 05", NativeCommand("m 5")), ("6D 06", NativeCommand("m 6")),
    ("6D 05 0A", NativeCommand("m 5 t", (10,))),
    ("6D 07", NativeCommand("m 7")), ("6D 08", NativeCommand("m 8")),
    ("6D 0A", NativeCommand("m 10")),
    ("56 00", NativeCommand("V 0")), ("56 01", NativeCommand("V 1")),
    ("56 02", NativeCommand("V 2")), ("56 03", NativeCommand("V 3")),
    ("6A 00", NativeCommand("j 0")), ("6A 01", NativeCommand("j 1")),
    ("6A 02", NativeCommand("j 2")),
    ("48 00", NativeCommand("H 0")), ("48 01", NativeCommand("H 1")),
]


@pytest.mark.parametrize(("hex_bytes", "command"), EVERY_COMMAND)
def test_every_command_decodes_and_encodes_back(hex_bytes: str, command: NativeCommand) -> None:
    payload = bytes.fromhex(hex_bytes)
    assert parse_command(payload) == command
    assert encode_command(command) == payload


def test_builders_give_the_documented_frames() -> None:
    assert frame(c.start_navigation()) == bytes.fromhex("CD EB D7 02 6D 00")
    assert frame(c.go_to_goal(3)) == bytes.fromhex("CD EB D7 02 67 03")
    assert frame(c.insert_goal(1.0, -2.5)) == bytes.fromhex(
        "CD EB D7 0A 67 69 00 00 80 3F 00 00 20 C0")
    assert frame(c.teleop("f", 50)) == bytes.fromhex("CD EB D7 02 66 32")
    assert frame(c.set_angle(1, 90)) == bytes.fromhex("CD EB D7 03 61 01 5A")
    assert frame(c.stop_loop()) == bytes.fromhex("CD EB D7 02 6D 06")  # A2: m 6, not m 4
    assert frame(c.set_loop_wait(7)) == bytes.fromhex("CD EB D7 03 6D 05 07")
    assert frame(c.shutdown()) == bytes.fromhex("CD EB D7 02 AA 44")
    assert frame(c.reset_goals()) == bytes.fromhex("CD EB D7 03 67 72 00")


@pytest.mark.parametrize("hex_bytes", [
    "6D 01",  # m 1 is no command
    "66 65",  # 101 % forward
    "61 02 10",  # sign 2
    "61 00 B5",  # 181 degrees
    "67 69 00 00",  # a cut insert
    "99", "", "6D 05 01 02",
])
def test_bytes_that_are_no_command_are_refused(hex_bytes: str) -> None:
    with pytest.raises(UnknownCommand):
        parse_command(bytes.fromhex(hex_bytes))


def test_bad_encodings_are_refused() -> None:
    with pytest.raises(UnknownCommand):
        encode_command(NativeCommand("x"))
    with pytest.raises(UnknownCommand):
        encode_command(NativeCommand("g", (300,)))
    with pytest.raises(ValueError, match="1..255"):
        frame(b"")


def test_the_reader_resynchronises_after_garbage_and_joins_split_frames() -> None:
    reader = FrameReader()
    stream = (b"\x00\xff\xcd\xeb" + frame(c.start_navigation()) + b"junk\xcd"
              + frame(c.go_to_goal(7)) + frame(c.insert_goal(2.0, 3.0)))
    got: list[bytes] = []
    for i in range(0, len(stream), 3):  # three bytes per read: every frame arrives split
        got += reader.feed(stream[i:i + 3])
    assert got == [c.start_navigation(), c.go_to_goal(7), c.insert_goal(2.0, 3.0)]


def test_the_reader_drops_bad_length_bytes_and_finds_the_next_frame() -> None:
    reader = FrameReader()
    bad = b"\xcd\xeb\xd7\x15" + bytes(21)  # LEN 21 > 20: dropped like the reference receiver
    empty = b"\xcd\xeb\xd7\x00"
    assert reader.feed(bad + empty + frame(c.pause())) == [c.pause()]
    assert reader.dropped == 2
    assert reader.feed(b"\xcd" * 10_000) == []  # a flood of garbage is not kept
    assert reader.feed(b"\xeb\xd7\x02m\x04") == [c.stop_navigation()]


def _worked_status() -> dict[str, float]:
    return {"navStatus": 1, "visualStatus": 1, "mapStatus": 0, "gcStatus": 0, "gbaStatus": 0,
            "chargeStatus": 0, "loopStatus": 0, "power": 12.5, "targetNumID": 3,
            "targetStatus": 1, "targetDistance": 2.0, "angleGoalStatus": -1,
            "controlSpeedX": 0.5, "controlSpeedTheta": 0.0, "currentSpeedX": 0.25,
            "currentSpeedTheta": -0.125, "currentPosX": 1.5, "currentPosY": -0.5,
            "currentAngle": 3.0, "busyStatus": 0}


def test_the_status_frame_is_the_worked_example_byte_for_byte() -> None:
    expected = bytes.fromhex(
        "CD EB D7 55 01 00 00 00 01 00 00 00 00 00 00 00"
        "00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00"
        "00 00 48 41 03 00 00 00 01 00 00 00 00 00 00 40"
        "FF FF FF FF 00 00 00 3F 00 00 00 00 00 00 80 3E"
        "00 00 00 BE E8 03 00 00 00 00 C0 3F 00 00 00 BF"
        "00 00 40 40 00 00 00 00 00")
    packed = pack_status(_worked_status(), 1000)
    assert len(packed) == STATUS_FRAME_SIZE == 89
    assert packed == expected
    back = unpack_status(packed)
    assert back["time_stamp"] == 1000 and back["power"] == 12.5 and back["targetNumID"] == 3
    assert struct.unpack_from("<i", packed, 48)[0] == -1  # angle_goal_status at frame offset 48


def test_a_damaged_status_frame_is_refused() -> None:
    packed = pack_status(_worked_status(), 1)
    for bad in (packed[:-1], b"\x00" + packed[1:], packed[:3] + b"\x31" + packed[4:]):
        with pytest.raises(ValueError, match="status frame"):
            unpack_status(bad)
    assert unpack_status(pack_status(_worked_status(), 2**32 + 5))["time_stamp"] == 5
