"""The 89-byte serial status frame (galileo-wire-protocols §1.3): 21 little-endian 4-byte fields.

Packed from the GalileoStatus object the HTTP API and the WebSocket serve
(:func:`polynav.protocols.galileo.status.galileo_status`), so every wire reports one state.
``time_stamp`` is a frame counter, +1 per frame (A5).
"""

from __future__ import annotations

import struct
from typing import Any

from polynav.protocols.galileo.native.commands import HEADER

#: (struct member, GalileoStatus field, struct code), in the frame's order.
FIELDS: tuple[tuple[str, str, str], ...] = (
    ("nav_status", "navStatus", "i"),
    ("visual_status", "visualStatus", "i"),
    ("map_status", "mapStatus", "i"),
    ("gc_status", "gcStatus", "i"),
    ("gba_status", "gbaStatus", "i"),
    ("charge_status", "chargeStatus", "i"),
    ("loop_status", "loopStatus", "i"),
    ("power", "power", "f"),
    ("target_numID", "targetNumID", "i"),
    ("target_status", "targetStatus", "i"),
    ("target_distance", "targetDistance", "f"),
    ("angle_goal_status", "angleGoalStatus", "i"),
    ("control_speed_x", "controlSpeedX", "f"),
    ("control_speed_theta", "controlSpeedTheta", "f"),
    ("current_speed_x", "currentSpeedX", "f"),
    ("current_speed_theta", "currentSpeedTheta", "f"),
    ("time_stamp", "time_stamp", "I"),
    ("current_pose_x", "currentPosX", "f"),
    ("current_pose_y", "currentPosY", "f"),
    ("current_angle", "currentAngle", "f"),
    ("busy_status", "busyStatus", "i"),
)
_BODY = struct.Struct("<" + "".join(code for _, _, code in FIELDS))
#: LEN of the status frame: 21 fields and the terminator (85, ``0x55``).
STATUS_LEN = _BODY.size + 1
STATUS_FRAME_SIZE = len(HEADER) + 1 + STATUS_LEN


def pack_status(status: dict[str, Any], time_stamp: int) -> bytes:
    """The frame of ``status`` (a GalileoStatus object) with ``time_stamp`` (wrapped to 32 bits)."""
    values: list[float] = []
    for _, key, code in FIELDS:
        if key == "time_stamp":
            values.append(time_stamp & 0xFFFFFFFF)
        elif code == "f":
            values.append(float(status[key]))
        else:
            values.append(int(status[key]))
    return HEADER + bytes([STATUS_LEN]) + _BODY.pack(*values) + b"\x00"


def unpack_status(frame: bytes) -> dict[str, Any]:
    """The fields of a status frame under their GalileoStatus names (and ``time_stamp``).

    Raises:
        ValueError: not a whole status frame.
    """
    if len(frame) != STATUS_FRAME_SIZE or not frame.startswith(HEADER) \
            or frame[3] != STATUS_LEN or frame[-1] != 0:
        raise ValueError(f"not a {STATUS_FRAME_SIZE}-byte status frame: {frame[:8].hex(' ')}...")
    values = _BODY.unpack(frame[4:-1])
    return {key: value for (_, key, _), value in zip(FIELDS, values, strict=True)}
