"""The Galileo native command bytes (galileo-wire-protocols §1.2, §1.4): framing and codec.

The same payloads travel over the serial line (framed ``CD EB D7 LEN payload``), in the ROS
message ``/galileo/cmds`` (``length`` and ``data``), and from the SDK. A payload is dispatched
on its whole length (A12): ``m 5`` with two bytes starts the patrol, ``m 5 t`` with three sets
its dwell time; ``g n`` goes to a goal, ``g i x y`` inserts one, ``g r 0`` resets them.
"""

from __future__ import annotations

import struct
from collections.abc import Callable
from dataclasses import dataclass

#: The frame header of both directions.
HEADER = b"\xcd\xeb\xd7"
#: The longest command payload a receiver keeps; the reference receiver drops longer ones.
MAX_COMMAND_LEN = 20
#: The buffered bytes a reader keeps while it waits for a header (garbage is dropped beyond).
_MAX_PENDING = 4096


class UnknownCommand(ValueError):
    """Bytes that are no command of §1.4."""


@dataclass(frozen=True, slots=True)
class NativeCommand:
    """A decoded command.

    Attributes:
        name: the command as the spec writes it: ``"m 0"``, ``"g"``, ``"g i"``, ``"g r 0"``,
            ``"i 1"``, ``"f"``, ``"a"``, ``"m 5 t"``, ``"V 2"``, ``"shutdown"``, ...
        args: its operands: ``g`` (goal number), ``g i`` (x, y), teleop letters (percent),
            ``a`` (sign, angle), ``m 5 t`` (seconds); empty for the rest.
    """

    name: str
    args: tuple[float, ...] = ()


# Two-byte commands whose second byte is fixed: payload -> name.
_FIXED: dict[bytes, str] = {
    b"m\x00": "m 0", b"m\x04": "m 4", b"m\x09": "m 9",
    b"m\x05": "m 5", b"m\x06": "m 6", b"m\x07": "m 7", b"m\x08": "m 8", b"m\x0a": "m 10",
    b"i\x00": "i 0", b"i\x01": "i 1", b"i\x02": "i 2",
    b"V\x00": "V 0", b"V\x01": "V 1", b"V\x02": "V 2", b"V\x03": "V 3",
    b"j\x00": "j 0", b"j\x01": "j 1", b"j\x02": "j 2",
    b"H\x00": "H 0", b"H\x01": "H 1",
    b"\xaa\x44": "shutdown",
}
_FIXED_BYTES = {name: payload for payload, name in _FIXED.items()}
#: Teleop letters (§1.4.6): forward, backward, turn left, turn right, stop.
TELEOP = ("f", "b", "c", "d", "s")


def parse_command(payload: bytes) -> NativeCommand:
    """The command ``payload`` carries (header and length byte removed).

    Raises:
        UnknownCommand: no command of §1.4 has these bytes, or an operand is out of its range.
    """
    if payload in _FIXED:
        return NativeCommand(_FIXED[payload])
    size = len(payload)
    letter = payload[:1]
    if size == 2 and letter == b"g":
        return NativeCommand("g", (payload[1],))
    if size == 2 and letter.decode("latin-1") in TELEOP:
        if payload[1] > 100:
            raise UnknownCommand(f"{letter.decode()} {payload[1]}: a percentage is 0..100")
        return NativeCommand(letter.decode(), (payload[1],))
    if size == 10 and payload[:2] == b"gi":
        x, y = struct.unpack("<ff", payload[2:])
        return NativeCommand("g i", (x, y))
    if payload == b"gr\x00":
        return NativeCommand("g r 0")
    if size == 3 and letter == b"a":
        sign, angle = payload[1], payload[2]
        if sign > 1 or angle > 180:
            raise UnknownCommand(f"a {sign} {angle}: sign is 0 or 1, angle 0..180")
        return NativeCommand("a", (sign, angle))
    if size == 3 and payload[:2] == b"m\x05":
        return NativeCommand("m 5 t", (payload[2],))
    raise UnknownCommand(f"no native command is {payload.hex(' ')}")


def encode_command(command: NativeCommand) -> bytes:
    """The payload of ``command`` (the inverse of :func:`parse_command`).

    Raises:
        UnknownCommand: an unknown name or operands out of range.
    """
    name, args = command.name, command.args
    if name in _FIXED_BYTES:
        return _FIXED_BYTES[name]
    try:
        if name == "g":
            return b"g" + bytes([int(args[0])])
        if name in TELEOP:
            return name.encode() + bytes([int(args[0])])
        if name == "g i":
            return b"gi" + struct.pack("<ff", float(args[0]), float(args[1]))
        if name == "g r 0":
            return b"gr\x00"
        if name == "a":
            return b"a" + bytes([int(args[0]), int(args[1])])
        if name == "m 5 t":
            return b"m\x05" + bytes([int(args[0])])
    except (IndexError, ValueError, struct.error) as exc:
        raise UnknownCommand(f"{name} {args}: {exc}") from None
    raise UnknownCommand(f"no native command is named {name!r}")


def frame(payload: bytes) -> bytes:
    """``payload`` as a serial frame: header, length byte, payload."""
    if not 0 < len(payload) <= 255:
        raise ValueError(f"a frame carries 1..255 bytes, not {len(payload)}")
    return HEADER + bytes([len(payload)]) + payload


class FrameReader:
    """Command payloads out of a serial byte stream.

    Resynchronises on the header anywhere in the stream (garbage before it is dropped), keeps a
    frame split across reads until its rest arrives, and drops a frame whose length byte is 0 or
    above :data:`MAX_COMMAND_LEN` (as the reference receiver does), looking for the next header
    right after the bad one.
    """

    def __init__(self, max_len: int = MAX_COMMAND_LEN) -> None:
        self._buffer = bytearray()
        self._max_len = max_len
        self.dropped = 0  # frames with a bad length byte
        self.skipped = 0  # bytes before a header (garbage)

    def feed(self, data: bytes) -> list[bytes]:
        self._buffer += data
        out: list[bytes] = []
        buf = self._buffer
        while True:
            start = buf.find(HEADER)
            if start < 0:
                keep = _partial_header(buf)
                self.skipped += len(buf) - keep
                del buf[:len(buf) - keep]
                break
            if start:
                self.skipped += start
                del buf[:start]
            if len(buf) < 4:
                break
            size = buf[3]
            if size == 0 or size > self._max_len:
                self.dropped += 1
                del buf[:3]
                continue
            if len(buf) < 4 + size:
                break
            out.append(bytes(buf[4:4 + size]))
            del buf[:4 + size]
        if len(buf) > _MAX_PENDING:
            self.skipped += len(buf) - _MAX_PENDING
            del buf[:-_MAX_PENDING]
        return out


def _partial_header(buf: bytearray) -> int:
    """How many trailing bytes of ``buf`` could begin a header."""
    for keep in (2, 1):
        if len(buf) >= keep and bytes(buf[-keep:]) == HEADER[:keep]:
            return keep
    return 0


def _fixed(name: str) -> Callable[[], bytes]:
    payload = _FIXED_BYTES[name]
    return lambda: payload


# Builders, one per command (what the SDK and tests send).
start_navigation = _fixed("m 0")
stop_navigation = _fixed("m 4")
reload_navigation = _fixed("m 9")
start_loop = _fixed("m 5")
stop_loop = _fixed("m 6")
enable_dispatch = _fixed("m 7")
disable_dispatch = _fixed("m 8")
reload_dispatch = _fixed("m 10")
pause = _fixed("i 0")
resume = _fixed("i 1")
cancel = _fixed("i 2")
start_mapping = _fixed("V 0")
stop_mapping = _fixed("V 1")
save_map = _fixed("V 2")
update_map = _fixed("V 3")
start_charge = _fixed("j 0")
stop_charge = _fixed("j 1")
save_charge_dock = _fixed("j 2")
enable_greeting = _fixed("H 0")
disable_greeting = _fixed("H 1")
shutdown = _fixed("shutdown")


def go_to_goal(number: int) -> bytes:
    return encode_command(NativeCommand("g", (number,)))


def insert_goal(x: float, y: float) -> bytes:
    return encode_command(NativeCommand("g i", (x, y)))


def reset_goals() -> bytes:
    return b"gr\x00"


def teleop(letter: str, percent: int) -> bytes:
    return encode_command(NativeCommand(letter, (percent,)))


def set_angle(sign: int, angle: int) -> bytes:
    return encode_command(NativeCommand("a", (sign, angle)))


def set_loop_wait(seconds: int) -> bytes:
    return encode_command(NativeCommand("m 5 t", (seconds,)))
