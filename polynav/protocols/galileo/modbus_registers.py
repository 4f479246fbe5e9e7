"""The Galileo Modbus register map (spec galileo-wire-protocols §3): what each address reads.

Pure functions from one :class:`Reading` of the robot to the four Modbus tables, and the word
codecs they use. Addresses here are PDU addresses: the document's address N of a table (reference
``0000N``, ``1000N``, ``3000N``, ``4000N``) is PDU N - 1 (spec §3.1, A7). Values wider than one
register follow the document's ``byteorder=Big, wordorder=Little``: each register big-endian on
the wire, the lower-address register holding the low 16 bits.

The server (:mod:`polynav.protocols.galileo.modbus`) builds a fresh :class:`Reading` for every
request, so nothing here is ever stale.
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass
from typing import Any

from polynav.geometry import Pose2D

# -- table sizes (every documented address, reserved ones included) ------------------------------

#: Discrete inputs 10001-10024.
DISCRETE_INPUTS = 24
#: Coils 00001-00022.
COILS = 22
#: Input registers 30001-30027 (30023 is the document's gap; it reads 0, A7).
INPUT_REGISTERS = 27
#: Holding registers 40001-40014.
HOLDING_REGISTERS = 14

# -- discrete inputs (PDU addresses) -------------------------------------------------------------
DI_NAVIGATION = 0
DI_MAPPING = 1
DI_GC = 2
DI_GBA = 3
DI_LOCAL_CHARGING = 4
DI_CHARGE_TASK = 5
DI_LOOP = 6
#: Virtual IO 0-7 (10017-10024): the expansion board's inputs 0-7.
DI_VIRTUAL_IO = 16

# -- coils ---------------------------------------------------------------------------------------
CO_NAVIGATION = 0
CO_MAPPING = 1
CO_SHUTDOWN = 2
CO_LOOP = 3
CO_CHARGE = 4
CO_RESERVED = range(5, 14)
#: Virtual IO 8-15 (00015-00022): the expansion board's outputs 0-7.
CO_VIRTUAL_IO = 14
VIRTUAL_IO_PORTS = 8

# -- input registers -----------------------------------------------------------------------------
IR_VISUAL = 0
IR_POWER = 1
IR_TARGET_ID = 3
IR_TARGET_STATUS = 4
IR_TARGET_DISTANCE = 5
IR_CONTROL_SPEED_X = 7
IR_CONTROL_SPEED_THETA = 9
IR_SPEED_X = 11
IR_SPEED_THETA = 13
IR_POSE_X = 15
IR_POSE_Y = 17
IR_ANGLE = 19
IR_TRACKED_POINTS = 21
# 22 (30023): the document's gap, reads 0
IR_STAMP_SECS = 23
IR_STAMP_NSECS = 25

# -- holding registers ---------------------------------------------------------------------------
HR_TELEOP_LINEAR = 0
HR_TELEOP_ANGULAR = 2
HR_GOAL_INDEX = 4
HR_PAUSE = 5
HR_CANCEL = 6
HR_GOAL_X = 7
HR_GOAL_Y = 9
HR_GOAL_THETA = 11
HR_LOOP_WAIT = 13

#: ``chargeStatus`` values (spec §1.3.1): on the pile (charging, charged) ...
ON_PILE = (1, 2)
#: ... and on the way to it (finding, docking).
CHARGE_TASK_STEPS = (3, 4)
#: ``targetStatus`` of a paused goal.
TARGET_PAUSED = 2

INT16_MIN, INT16_MAX = -0x8000, 0x7FFF
FLOAT32_MAX = 3.4028234663852886e38


# -- word codecs ---------------------------------------------------------------------------------

def int16_word(value: int) -> int:
    """``value`` as one register (two's complement), clamped to int16's range."""
    return max(INT16_MIN, min(INT16_MAX, int(value))) & 0xFFFF


def word_int16(word: int) -> int:
    """One register read as a signed int16."""
    return word - 0x10000 if word & 0x8000 else word


def float32_words(value: float) -> list[int]:
    """``value`` as float32 in two registers, low word first (beyond float32's range: +-inf)."""
    value = float(value)
    if math.isfinite(value) and abs(value) > FLOAT32_MAX:
        value = math.copysign(math.inf, value)
    (raw,) = struct.unpack(">I", struct.pack(">f", value))
    return [raw & 0xFFFF, raw >> 16]


def words_float32(low: int, high: int) -> float:
    """Two registers (low word first) read as a float32."""
    (value,) = struct.unpack(">f", struct.pack(">I", ((high & 0xFFFF) << 16) | (low & 0xFFFF)))
    return float(value)


def uint32_words(value: int) -> list[int]:
    """``value`` as uint32 in two registers, low word first (clamped to uint32's range)."""
    raw = max(0, min(0xFFFFFFFF, int(value)))
    return [raw & 0xFFFF, raw >> 16]


# -- the robot at one instant --------------------------------------------------------------------

@dataclass(frozen=True, slots=True)
class Reading:
    """What the four tables show at one instant.

    Attributes:
        status: the GalileoStatus dict (:func:`polynav.protocols.galileo.status.galileo_status`),
            its ``header.stamp`` on the runtime's clock.
        tracked_points: how many scan returns localization tracks (0 while not tracking).
        io_inputs, io_outputs: the expansion board's inputs and outputs (virtual IO 0-7, 8-15).
        teleop: the teleop command (linear [m/s], angular [rad/s]) in force, zeros after its
            dead-man timeout.
        goal: the pose goal of the current or last navigation attempt, if any.
        loop_wait: the patrol dwell time at each goal [s].
    """

    status: dict[str, Any]
    tracked_points: int
    io_inputs: tuple[int, ...]
    io_outputs: tuple[int, ...]
    teleop: tuple[float, float]
    goal: Pose2D | None
    loop_wait: int


def _bits(values: list[int]) -> list[bool]:
    return [bool(v) for v in values]


def _padded(levels: tuple[int, ...]) -> list[int]:
    return [int(v) for v in (list(levels) + [0] * VIRTUAL_IO_PORTS)[:VIRTUAL_IO_PORTS]]


def discrete_inputs(r: Reading) -> list[bool]:
    """Discrete inputs 10001-10024."""
    s = r.status
    values = [0] * DISCRETE_INPUTS
    values[DI_NAVIGATION] = s["navStatus"] == 1
    values[DI_MAPPING] = s["mapStatus"] == 1
    values[DI_GC] = s["gcStatus"] == 1
    values[DI_GBA] = s["gbaStatus"] == 1
    values[DI_LOCAL_CHARGING] = s["chargeStatus"] in ON_PILE
    values[DI_CHARGE_TASK] = s["chargeStatus"] in CHARGE_TASK_STEPS
    values[DI_LOOP] = s["loopStatus"] == 1
    values[DI_VIRTUAL_IO:] = _padded(r.io_inputs)
    return _bits(values)


def coils(r: Reading) -> list[bool]:
    """Coils 00001-00022: each switch reads the state it switches (shutdown reads 0)."""
    s = r.status
    values = [0] * COILS
    values[CO_NAVIGATION] = s["navStatus"] == 1
    values[CO_MAPPING] = s["mapStatus"] == 1
    values[CO_LOOP] = s["loopStatus"] == 1
    values[CO_CHARGE] = s["chargeStatus"] in CHARGE_TASK_STEPS
    values[CO_VIRTUAL_IO:] = _padded(r.io_outputs)
    return _bits(values)


def input_registers(r: Reading) -> list[int]:
    """Input registers 30001-30027."""
    s = r.status
    stamp = s["header"]["stamp"]
    words = [0] * INPUT_REGISTERS
    words[IR_VISUAL] = int16_word(s["visualStatus"])
    words[IR_TARGET_ID] = int16_word(s["targetNumID"])
    words[IR_TARGET_STATUS] = int16_word(s["targetStatus"])
    words[IR_TRACKED_POINTS] = int16_word(r.tracked_points)
    for address, key in ((IR_POWER, "power"), (IR_TARGET_DISTANCE, "targetDistance"),
                         (IR_CONTROL_SPEED_X, "controlSpeedX"),
                         (IR_CONTROL_SPEED_THETA, "controlSpeedTheta"),
                         (IR_SPEED_X, "currentSpeedX"), (IR_SPEED_THETA, "currentSpeedTheta"),
                         (IR_POSE_X, "currentPosX"), (IR_POSE_Y, "currentPosY"),
                         (IR_ANGLE, "currentAngle")):
        words[address:address + 2] = float32_words(s[key])
    words[IR_STAMP_SECS:IR_STAMP_SECS + 2] = uint32_words(stamp["secs"])
    words[IR_STAMP_NSECS:IR_STAMP_NSECS + 2] = uint32_words(stamp["nsecs"])
    return words


def holding_registers(r: Reading) -> list[int]:
    """Holding registers 40001-40014: each reads the state its write drives (cancel reads 0)."""
    s = r.status
    goal = r.goal if r.goal is not None else Pose2D()
    words = [0] * HOLDING_REGISTERS
    words[HR_TELEOP_LINEAR:HR_TELEOP_LINEAR + 2] = float32_words(r.teleop[0])
    words[HR_TELEOP_ANGULAR:HR_TELEOP_ANGULAR + 2] = float32_words(r.teleop[1])
    words[HR_GOAL_INDEX] = int16_word(s["targetNumID"])
    words[HR_PAUSE] = int(s["targetStatus"] == TARGET_PAUSED)
    words[HR_CANCEL] = 0
    for address, value in ((HR_GOAL_X, goal.x), (HR_GOAL_Y, goal.y), (HR_GOAL_THETA, goal.theta)):
        words[address:address + 2] = float32_words(value)
    words[HR_LOOP_WAIT] = int16_word(r.loop_wait)
    return words
