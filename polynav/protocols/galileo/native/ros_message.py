"""``galileo_msg/GalileoNativeCmds`` as JSON (galileo-wire-protocols §2.2): one native command,
the serial header replaced by a ``std_msgs/Header``, the length byte in ``length``, the command
bytes in ``data``.

``data`` is a ``uint8[]``: rosbridge sends such arrays as base64 text and other JSON clients as a
list of numbers, so both are taken. ``length`` must count ``data`` (the serial receiver relies on
it); ``header`` may be left out (the ``rostopic pub`` example fills it with zeros).
"""

from __future__ import annotations

import base64
import binascii
from typing import Any

from polynav.protocols.galileo.native.commands import MAX_COMMAND_LEN

#: The type name as Galileo's 000 firmware names it (001: ``galileo_serial_server/...``).
NATIVE_CMDS_TYPE = "galileo_msg/GalileoNativeCmds"


def decode_native_cmds(message: Any) -> bytes:
    """The command bytes of a GalileoNativeCmds message.

    Raises:
        ValueError: not such a message (what is wrong is said).
    """
    if not isinstance(message, dict):
        raise ValueError("a GalileoNativeCmds is an object {header, length, data}")
    data = message.get("data")
    if isinstance(data, str):
        try:
            payload = base64.b64decode(data, validate=True)
        except (binascii.Error, ValueError):
            raise ValueError("data: a uint8[] as text must be base64") from None
    elif isinstance(data, list):
        if not all(isinstance(b, int) and not isinstance(b, bool) and 0 <= b <= 255
                   for b in data):
            raise ValueError("data: every byte is an integer 0..255")
        payload = bytes(data)
    else:
        raise ValueError("data: the command bytes (a list of 0..255 or base64 text) are missing")
    length = message.get("length", len(payload))
    if not isinstance(length, int) or isinstance(length, bool):
        raise ValueError("length: an unsigned integer")
    if length != len(payload):
        raise ValueError(f"length {length} does not count data ({len(payload)} bytes)")
    if not 0 < len(payload) <= MAX_COMMAND_LEN:
        raise ValueError(f"a command has 1..{MAX_COMMAND_LEN} bytes, not {len(payload)}")
    return payload


def encode_native_cmds(payload: bytes, seq: int = 0, stamp: float = 0.0,
                       frame_id: str = "galileo_msg") -> dict[str, Any]:
    """The message carrying ``payload`` (``data`` as a list of numbers)."""
    secs = int(stamp)
    return {"header": {"seq": seq, "stamp": {"secs": secs, "nsecs": int((stamp - secs) * 1e9)},
                       "frame_id": frame_id},
            "length": len(payload), "data": list(payload)}
