"""The Galileo Modbus TCP server (galileo-wire-protocols §3) with a real pymodbus client over
TCP: every register of the spec read and checked against the runtime, the robot driven by the
coils and holding registers on simulated time, and the protocol's own errors for bad requests.

The expected values here are worked out from the spec's tables (PDU address = doc address - 1,
``byteorder=Big, wordorder=Little``) with pymodbus's own codecs, not with the server's.
"""

from __future__ import annotations

import math
import socket
import struct
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

import pytest
from pymodbus.client import ModbusTcpClient
from pymodbus.exceptions import ModbusException
from pymodbus.pdu import ModbusPDU

from polynav.protocols.galileo.diagnostics import diagnostics
from polynav.protocols.galileo.native.control import native_control
from polynav.protocols.galileo.server import GalileoThread
from polynav.protocols.galileo.status import galileo_status
from polynav.runtime.robot_runtime import RobotRuntime
from tests.protocols.galileo import spec
from tests.protocols.galileo.conftest import Harness, galileo_config, serving

READS = "test_every_register_reads_the_runtime"
COVERED: dict[str, str] = {key: READS for key in spec.MODBUS}
COVERED.update({
    "galileo-modbus register 00001": "test_navigation_and_loop_coils",
    "galileo-modbus register 00002": "test_mapping_coil_starts_and_stops_mapping",
    "galileo-modbus register 00003": "test_shutdown_coil_powers_the_robot_off",
    "galileo-modbus register 00004": "test_navigation_and_loop_coils",
    "galileo-modbus register 00005": "test_charge_coil_runs_the_charge_task",
    "galileo-modbus register 40001": "test_teleop_registers_drive_the_robot",
    "galileo-modbus register 40003": "test_teleop_registers_drive_the_robot",
    "galileo-modbus register 40005": "test_goal_index_pause_resume_cancel",
    "galileo-modbus register 40006": "test_goal_index_pause_resume_cancel",
    "galileo-modbus register 40007": "test_goal_index_pause_resume_cancel",
    "galileo-modbus register 40008": "test_goal_pose_registers_drive_the_robot_there",
    "galileo-modbus register 40014": "test_navigation_and_loop_coils",
})
for _doc in range(15, 23):
    COVERED[f"galileo-modbus register {_doc:05d}"] = "test_virtual_io_coils_and_inputs"
for _doc in range(17, 25):
    COVERED[f"galileo-modbus register {10000 + _doc}"] = "test_virtual_io_coils_and_inputs"

ILLEGAL_ADDRESS, ILLEGAL_VALUE = 2, 3
FLOAT32 = ModbusTcpClient.DATATYPE.FLOAT32
UINT32 = ModbusTcpClient.DATATYPE.UINT32
INT16 = ModbusTcpClient.DATATYPE.INT16


@dataclass
class Bus:
    """The Galileo harness and a pymodbus client of the robot's Modbus server."""

    g: Harness
    client: ModbusTcpClient
    port: int

    def ok(self, response: ModbusPDU) -> ModbusPDU:
        assert not response.isError(), f"exception {getattr(response, 'exception_code', None)}"
        return response

    # Addresses are the references of the spec's tables: 00001 (coil), 10001, 30001, 40001.

    def inputs(self, ref: int, count: int = 1) -> list[bool]:
        return list(self.ok(self.client.read_discrete_inputs(_pdu(ref), count=count)
                            ).bits[:count])

    def coils(self, ref: int, count: int = 1) -> list[bool]:
        return list(self.ok(self.client.read_coils(_pdu(ref), count=count)).bits[:count])

    def input_words(self, ref: int, count: int = 1) -> list[int]:
        return list(self.ok(self.client.read_input_registers(_pdu(ref), count=count)
                            ).registers)

    def holding_words(self, ref: int, count: int = 1) -> list[int]:
        return list(self.ok(self.client.read_holding_registers(_pdu(ref), count=count)
                            ).registers)

    def input_float(self, ref: int) -> float:
        return _float(self.input_words(ref, 2))

    def input_int(self, ref: int) -> int:
        return _int16(self.input_words(ref))

    def write_coil(self, ref: int, on: bool) -> None:
        self.ok(self.client.write_coil(_pdu(ref), on))

    def write_words(self, ref: int, words: list[int]) -> None:
        self.ok(self.client.write_registers(_pdu(ref), words))

    def write_floats(self, ref: int, *values: float) -> None:
        words: list[int] = []
        for v in values:
            words += _words(v)
        self.write_words(ref, words)

    def refused(self, response: ModbusPDU) -> int:
        """The exception code of an error reply."""
        assert response.isError(), response
        return int(response.exception_code)

    def until(self, done: Callable[[], bool], timeout: float, step: float = 0.1) -> None:
        assert self.g.advance_until(done, timeout, step), "timed out"

    def status(self) -> dict[str, Any]:
        return galileo_status(self.g.server.ctx)


def _pdu(ref: int) -> int:
    """The PDU address of a table reference: doc address N = PDU N - 1 (spec §3.1)."""
    return ref % 10000 - 1


def _float(words: list[int]) -> float:
    return float(ModbusTcpClient.convert_from_registers(words, FLOAT32, word_order="little"))


def _words(value: float) -> list[int]:
    return ModbusTcpClient.convert_to_registers(value, FLOAT32, word_order="little")


def _int16(words: list[int]) -> int:
    return int(ModbusTcpClient.convert_from_registers(words, INT16))  # type: ignore[arg-type]


def _f32(value: float) -> float:
    """``value`` as a float32 holds it."""
    return float(struct.unpack("<f", struct.pack("<f", value))[0])


@pytest.fixture
def bus(runtime: RobotRuntime) -> Iterator[Bus]:
    with serving(runtime, galileo_config(modbus_port=0)) as galileo:
        port = galileo.server.modbus_port
        assert port is not None
        client = ModbusTcpClient("127.0.0.1", port=port, timeout=10, retries=0)
        try:
            assert client.connect()
            yield Bus(galileo, client, port)
        finally:
            client.close()


def _start_navigation(bus: Bus) -> None:
    """Navigation on floor1's default path from its target 1 (over HTTP, the Modbus table has
    no map or path to choose), localized."""
    bus.g.ok("GET", "/navigation/start",
             params={"map": "floor1", "path": "default", "start_index": 1})
    bus.until(lambda: bus.input_int(30001) == 1 and bus.inputs(10001) == [True], 20.0)


# -- reads ---------------------------------------------------------------------------------------

def _registers(entry: dict[str, Any]) -> int:
    title = entry["title"]
    return 6 if "6 regs" in title else 2 if "2 regs" in title else 1


def _expected(bus: Bus, status: dict[str, Any]) -> dict[str, Any]:
    """doc reference -> the value the spec's table says it holds, from the runtime now."""
    runtime = bus.g.runtime
    outputs, inputs = runtime.peripherals.io_state("expansion_io")
    scan = runtime.robot.read_scan()
    assert scan is not None
    valid = [r for r in scan.ranges.tolist() if math.isfinite(r)
             and scan.range_min <= r <= scan.range_max]
    snap = runtime.status()
    goal = snap.goal
    assert goal is not None
    stamp = status["header"]["stamp"]
    out: dict[str, Any] = {
        "10001": status["navStatus"] == 1, "10002": status["mapStatus"] == 1,
        "10003": status["gcStatus"] == 1, "10004": status["gbaStatus"] == 1,
        "10005": status["chargeStatus"] in (1, 2), "10006": status["chargeStatus"] in (3, 4),
        "10007": status["loopStatus"] == 1,
        "00001": status["navStatus"] == 1, "00002": status["mapStatus"] == 1, "00003": False,
        "00004": status["loopStatus"] == 1, "00005": status["chargeStatus"] in (3, 4),
        "30001": status["visualStatus"], "30002": _f32(status["power"]),
        "30004": status["targetNumID"], "30005": status["targetStatus"],
        "30006": _f32(status["targetDistance"]), "30008": _f32(status["controlSpeedX"]),
        "30010": _f32(status["controlSpeedTheta"]), "30012": _f32(status["currentSpeedX"]),
        "30014": _f32(status["currentSpeedTheta"]), "30016": _f32(status["currentPosX"]),
        "30018": _f32(status["currentPosY"]), "30020": _f32(status["currentAngle"]),
        "30022": len(valid) if status["visualStatus"] == 1 else 0,
        "30024": stamp["secs"], "30026": stamp["nsecs"],
        "40001": 0.0, "40003": 0.0, "40005": status["targetNumID"],
        "40006": int(status["targetStatus"] == 2), "40007": 0,
        "40008": [_f32(goal.x), _f32(goal.y), _f32(goal.theta)],
        "40014": native_control(bus.g.server.ctx).loop_wait,
    }
    for doc in range(8, 17):
        out[f"{10000 + doc}"] = False
    for doc in range(6, 15):
        out[f"{doc:05d}"] = False
    for k in range(8):
        out[f"{10017 + k}"] = bool(inputs[k])
        out[f"{15 + k:05d}"] = bool(outputs[k] or 0)
    return out


def _read_entry(bus: Bus, path: str, regs: int) -> Any:
    table, ref = path[0], int(path)
    if table == "1":
        return bus.inputs(ref)[0]
    if table == "0":
        return bus.coils(ref)[0]
    words = bus.input_words(ref, regs) if table == "3" else bus.holding_words(ref, regs)
    if regs == 1:
        return _int16(words)
    if path in ("30024", "30026"):
        return int(ModbusTcpClient.convert_from_registers(words, UINT32, word_order="little"))
    if regs == 6:
        return [_float(words[i:i + 2]) for i in (0, 2, 4)]
    return _float(words)


def test_every_register_reads_the_runtime(bus: Bus) -> None:
    """A robot working towards goal 2 with IO set: each entry read alone, then each table in
    one request, against the runtime at that same (simulated) instant."""
    g = bus.g
    devices = g.runtime.peripherals.devices
    devices.expansion_io.set_input(2, 1)  # type: ignore[attr-defined]
    devices.expansion_io.set_input(7, 1)  # type: ignore[attr-defined]
    g.runtime.peripherals.set_outputs("expansion_io", {0: 1, 5: 1, 6: 0})
    assert native_control(g.server.ctx).set_loop_wait(9).accepted
    _start_navigation(bus)
    bus.write_words(40005, [2])
    g.runtime.advance(3.0)  # moving, part-way
    g.runtime.run_between_ticks(lambda: None)  # the snapshot at this instant (a command's refresh)

    status = bus.status()
    assert (status["navStatus"], status["visualStatus"], status["targetNumID"],
            status["targetStatus"]) == (1, 1, 2, 1)
    assert status["currentSpeedX"] > 0.05 and status["targetDistance"] > 0.5
    expected = _expected(bus, status)
    assert expected["30022"] > 100  # a lidar's worth of tracked returns
    got = {e["path"]: _read_entry(bus, e["path"], _registers(e)) for e in spec.MODBUS.values()}
    assert got == expected
    assert sorted(got) == sorted(e["path"] for e in spec.MODBUS.values())

    # whole tables at once, unit id 7 as well as 1 (the document names none)
    assert bus.inputs(10001, 24) == [expected[f"{10001 + k}"] for k in range(24)]
    assert bus.coils(1, 22) == [expected[f"{1 + k:05d}"] for k in range(22)]
    words = bus.ok(bus.client.read_input_registers(0, count=27, device_id=7)).registers
    assert words[22] == 0  # 30023, the document's gap, reads 0
    assert _int16(words[0:1]) == expected["30001"] and _float(words[1:3]) == expected["30002"]
    assert _float(words[15:17]) == expected["30016"]
    assert words[23:27] == bus.input_words(30024, 4)
    holding = bus.holding_words(40001, 14)
    assert [_float(holding[i:i + 2]) for i in (7, 9, 11)] == expected["40008"]
    assert holding[13] == 9

    # the wire form of §3.1: float32 low word first, each word big-endian
    volts = status["power"]
    assert volts > 10.0
    raw = struct.unpack(">I", struct.pack(">f", volts))[0]
    assert bus.input_words(30002, 2) == [raw & 0xFFFF, raw >> 16]


def test_a_float_is_low_word_first_on_the_wire(bus: Bus) -> None:
    """The spec's worked example (§3.1): 12.5 is registers [0x0000, 0x4148]; x written alone
    waits for theta and reads back as written."""
    bus.write_words(40008, [0x0000, 0x4148])
    assert bus.holding_words(40008, 2) == [0x0000, 0x4148]
    assert _float(bus.holding_words(40008, 2)) == 12.5
    bus.write_words(40010, _words(0.2))
    assert bus.holding_words(40010, 2) == [0xCCCD, 0x3E4C]
    assert bus.g.runtime.status().goal is None  # nothing sent before theta


# -- writes --------------------------------------------------------------------------------------

def test_goal_pose_registers_drive_the_robot_there(bus: Bus) -> None:
    _start_navigation(bus)
    target = (5.0, 6.0, math.pi / 2)
    # one register at a time (FC 06), as a master without FC 16 would: acts on theta's high word
    words = _words(target[0]) + _words(target[1]) + _words(target[2])
    for k, word in enumerate(words):
        assert bus.g.runtime.status().goal is None  # nothing sent before theta's high word
        bus.ok(bus.client.write_register(_pdu(40008) + k, word))
    bus.g.runtime.advance(0.5)
    assert bus.input_int(30005) == 1  # working
    assert bus.input_int(30004) == -2  # a goal without a target index
    pose_words = bus.holding_words(40008, 6)
    assert [_float(pose_words[i:i + 2]) for i in (0, 2, 4)] == [_f32(v) for v in target]

    bus.until(lambda: bus.input_int(30005) == 0, 120.0, step=0.5)
    true = bus.g.runtime.simulation.true_pose
    assert math.hypot(true.x - target[0], true.y - target[1]) < 0.3
    assert abs(math.remainder(true.theta - target[2], math.tau)) < 0.2
    assert abs(_float(bus.input_words(30006, 2))) < 0.01  # distance: arrived


def test_goal_index_pause_resume_cancel(bus: Bus) -> None:
    _start_navigation(bus)
    bus.write_words(40005, [2])
    bus.g.runtime.advance(1.0)
    assert (bus.input_int(30004), bus.input_int(30005)) == (2, 1)
    assert bus.holding_words(40005, 3) == [2, 0, 0]

    bus.write_words(40006, [1])
    bus.until(lambda: bus.input_int(30005) == 2, 5.0)
    assert bus.holding_words(40006) == [1]
    bus.g.runtime.advance(1.0)
    assert abs(bus.input_float(30012)) < 0.02  # stopped while paused

    bus.write_words(40006, [0])
    bus.until(lambda: bus.input_int(30005) == 1, 5.0)
    assert bus.holding_words(40006) == [0]

    bus.ok(bus.client.write_register(_pdu(40007), 1))
    bus.until(lambda: bus.input_int(30005) == 0, 5.0)
    assert bus.holding_words(40007) == [0]  # "1 = cancel" reads back 0
    bus.g.runtime.advance(1.0)
    assert abs(bus.input_float(30012)) < 0.02


def test_navigation_and_loop_coils(bus: Bus) -> None:
    ctx = bus.g.server.ctx
    # loop without navigation: ignored, as on the serial line; the reply still echoes the write
    assert bus.ok(bus.client.write_coil(_pdu(4), True)).bits[0] is True
    bus.g.runtime.advance(0.5)
    assert bus.coils(4) == [False] and bus.inputs(10007) == [False]

    bus.write_coil(1, True)
    bus.until(lambda: bus.inputs(10001) == [True], 20.0)
    assert bus.coils(1) == [True]
    bus.write_coil(1, True)  # a level: writing it again changes nothing
    bus.g.runtime.advance(0.5)
    assert bus.coils(1) == [True]

    bus.write_words(40014, [3])
    assert native_control(ctx).loop_wait == 3 and bus.holding_words(40014) == [3]
    bus.until(lambda: bus.input_int(30001) == 1, 20.0)
    bus.write_coil(4, True)
    bus.until(lambda: bus.inputs(10007) == [True], 5.0)
    assert bus.coils(4) == [True] and bus.status()["loopStatus"] == 1
    bus.until(lambda: bus.input_int(30005) == 1, 10.0)  # patrolling a goal

    bus.write_coil(4, False)
    bus.until(lambda: bus.inputs(10007) == [False], 5.0)
    assert bus.coils(4) == [False]

    bus.write_coil(1, False)
    bus.until(lambda: bus.inputs(10001) == [False], 10.0)
    assert bus.coils(1) == [False] and bus.g.runtime.status().mode == "free"


def test_mapping_coil_starts_and_stops_mapping(bus: Bus) -> None:
    bus.write_coil(2, True)
    bus.until(lambda: bus.inputs(10002) == [True], 10.0)
    assert bus.coils(2) == [True] and bus.g.runtime.status().mode == "mapping"
    bus.g.runtime.advance(2.0)
    bus.write_coil(2, False)
    bus.until(lambda: bus.inputs(10002) == [False], 30.0)
    assert bus.coils(2) == [False] and bus.g.runtime.status().mode != "mapping"


def test_charge_coil_runs_the_charge_task(bus: Bus) -> None:
    _start_navigation(bus)
    bus.write_coil(5, True)
    bus.until(lambda: bus.inputs(10006) == [True], 5.0)  # finding the pile
    assert bus.coils(5) == [True] and bus.status()["chargeStatus"] in (3, 4)
    bus.until(lambda: bus.inputs(10005) == [True], 180.0, step=0.5)  # on the pile, charging
    assert bus.g.runtime.status().charging
    assert bus.inputs(10006) == [False] and bus.coils(5) == [False]
    bus.write_coil(5, False)  # the task is over: nothing to stop
    bus.g.runtime.advance(0.5)
    assert bus.inputs(10005) == [True]


def test_shutdown_coil_powers_the_robot_off(bus: Bus) -> None:
    bus.write_coil(3, False)  # 0: nothing
    bus.g.runtime.advance(11.0)
    assert bus.g.runtime.powered
    bus.write_coil(3, True)
    assert bus.coils(3) == [False]  # a one-shot: reads 0
    bus.g.runtime.advance(10.5)
    assert not bus.g.runtime.powered
    # the server still answers, and takes writes it cannot carry out as ignored commands
    assert bus.inputs(10001, 24) == [False] * 24 and bus.coils(1, 22) == [False] * 22
    words = bus.input_words(30001, 27)
    assert _int16(words[0:1]) == -1 and words[21] == 0  # visual system off, no tracked points
    assert len(bus.holding_words(40001, 14)) == 14
    bus.ok(bus.client.write_coils(_pdu(15), [True] * 8))
    bus.write_coil(1, True)
    bus.write_floats(40001, 0.2, 0.0)
    bus.g.runtime.advance(1.0)
    assert not bus.g.runtime.powered and bus.g.runtime.status().mode != "navigating"


def test_teleop_registers_drive_the_robot(bus: Bus) -> None:
    before = bus.g.runtime.simulation.true_pose
    bus.write_floats(40001, 0.3, 0.2)
    bus.g.runtime.advance(0.4)
    assert [_float(bus.holding_words(40001, 2)), _float(bus.holding_words(40003, 2))] == [
        _f32(0.3), _f32(0.2)]
    assert bus.input_float(30012) > 0.1 and bus.input_float(30014) > 0.05
    moved = bus.g.runtime.simulation.true_pose
    assert math.hypot(moved.x - before.x, moved.y - before.y) > 0.02
    # the angular speed alone (low then high word): the linear one in force is kept
    bus.write_floats(40003, -0.2)
    bus.g.runtime.advance(0.3)
    assert bus.input_float(30014) < -0.05 and bus.input_float(30012) > 0.1
    bus.g.runtime.advance(1.5)  # no new command: the dead-man stops the robot
    assert bus.holding_words(40001, 4) == [0, 0, 0, 0]
    assert abs(bus.input_float(30012)) < 0.02


def test_virtual_io_coils_and_inputs(bus: Bus) -> None:
    runtime = bus.g.runtime
    levels = [True, False, True, True, False, False, True, False]
    bus.ok(bus.client.write_coils(14, levels))  # 00015-00022: virtual IO 8-15
    outputs, _ = runtime.peripherals.io_state("expansion_io")
    assert outputs == [int(v) for v in levels]
    assert bus.coils(15, 8) == levels
    bus.write_coil(16, True)
    assert runtime.peripherals.io_state("expansion_io")[0][1] == 1

    expansion = runtime.peripherals.devices.expansion_io
    for port in (0, 3, 7):
        expansion.set_input(port, 1)  # type: ignore[attr-defined]
    assert bus.inputs(10017, 8) == [True, False, False, True, False, False, False, True]
    expansion.set_input(3, 0)  # type: ignore[attr-defined]
    assert bus.inputs(10020) == [False]


# -- bad requests --------------------------------------------------------------------------------

def test_addresses_outside_the_map_get_exception_2(bus: Bus) -> None:
    c = bus.client
    assert bus.refused(c.read_discrete_inputs(24)) == ILLEGAL_ADDRESS
    assert bus.refused(c.read_discrete_inputs(20, count=5)) == ILLEGAL_ADDRESS
    assert bus.refused(c.read_coils(22)) == ILLEGAL_ADDRESS
    assert bus.refused(c.read_input_registers(27)) == ILLEGAL_ADDRESS
    assert bus.refused(c.read_input_registers(26, count=2)) == ILLEGAL_ADDRESS
    assert bus.refused(c.read_holding_registers(14)) == ILLEGAL_ADDRESS
    assert bus.refused(c.read_holding_registers(0, count=15)) == ILLEGAL_ADDRESS
    assert bus.refused(c.read_holding_registers(1000)) == ILLEGAL_ADDRESS
    assert bus.refused(c.write_coil(22, True)) == ILLEGAL_ADDRESS
    assert bus.refused(c.write_register(14, 1)) == ILLEGAL_ADDRESS
    assert bus.refused(c.write_registers(12, [0, 0, 0])) == ILLEGAL_ADDRESS
    assert bus.inputs(10001, 24) == bus.inputs(10001, 24)  # still serving
    counts = diagnostics(bus.g.server.ctx).snapshot()  # each refusal counted
    assert counts["modbus.read_exception_2"] == 8 and counts["modbus.write_exception_2"] == 3


def test_bad_values_get_exception_3_and_change_nothing(bus: Bus) -> None:
    _start_navigation(bus)
    c = bus.client
    ctx = bus.g.server.ctx
    assert bus.refused(c.write_register(4, 99)) == ILLEGAL_VALUE  # goal 99 of 3
    assert bus.refused(c.write_register(4, 0xFFFF)) == ILLEGAL_VALUE  # goal -1
    assert bus.refused(c.write_register(5, 2)) == ILLEGAL_VALUE  # pause is 0/1
    assert bus.refused(c.write_register(6, 7)) == ILLEGAL_VALUE  # cancel is 1 (or 0)
    assert bus.refused(c.write_register(13, 256)) == ILLEGAL_VALUE  # loop wait 0..255
    assert bus.refused(c.write_register(13, 0xFFFF)) == ILLEGAL_VALUE
    nan = _words(math.nan)
    assert bus.refused(c.write_registers(7, _words(1.0) + nan + _words(0.0))) == ILLEGAL_VALUE
    assert bus.refused(c.write_registers(0, _words(math.inf))) == ILLEGAL_VALUE
    assert bus.refused(c.write_coil(5, True)) == ILLEGAL_VALUE  # reserved coil 00006
    # one bad value refuses the whole request: navigation is not stopped
    assert bus.refused(c.write_coils(0, [False, False, False, False, False, True])) \
        == ILLEGAL_VALUE
    bus.g.runtime.advance(1.0)
    status = bus.status()
    assert status["navStatus"] == 1 and status["targetStatus"] == -1
    assert bus.g.runtime.status().goal is None
    assert native_control(ctx).loop_wait == 0
    assert bus.holding_words(40001, 14)[7:13] == [0] * 6  # the refused pose left nothing pending
    assert diagnostics(ctx).snapshot()["modbus.write_exception_3"] == 10


def test_garbage_on_the_socket_is_no_crash(bus: Bus) -> None:
    with socket.create_connection(("127.0.0.1", bus.port), timeout=5) as raw:
        raw.sendall(b"\x00\x01\x00\x00\x00\x06\x01\x63\x00\x00\x00\x01")  # function 0x63
        reply = raw.recv(64)
        assert reply[7] & 0x80 and reply[8] == 1  # pymodbus's answer: illegal function
        raw.sendall(b"\xff" * 300)
    assert len(bus.inputs(10001, 24)) == 24  # the server still answers


def test_clients_at_once_and_a_taken_port(bus: Bus) -> None:
    port = bus.port
    errors: list[BaseException] = []

    def reads() -> None:
        try:
            with ModbusTcpClient("127.0.0.1", port=port, timeout=10, retries=0) as other:
                for _ in range(30):
                    assert len(other.read_input_registers(0, count=27).registers) == 27
        except BaseException as exc:  # noqa: BLE001 - handed to the test thread
            errors.append(exc)

    threads = [threading.Thread(target=reads) for _ in range(3)]
    for t in threads:
        t.start()
    for _ in range(30):
        assert len(bus.coils(1, 22)) == 22
    for t in threads:
        t.join(timeout=30)
    assert errors == []

    with pytest.raises(OSError, match="cannot listen"):
        GalileoThread(bus.g.runtime, galileo_config(modbus_port=port))
    assert len(bus.inputs(10001, 24)) == 24  # the first server is untouched


def test_stop_closes_the_connections(runtime: RobotRuntime) -> None:
    server = GalileoThread(runtime, galileo_config(modbus_port=0))
    port = server.modbus_port
    assert port is not None
    with ModbusTcpClient("127.0.0.1", port=port, timeout=2, retries=0) as client:
        assert not client.read_coils(0).isError()
        server.stop()
        with pytest.raises(ModbusException):
            client.read_coils(0)


def test_every_modbus_entry_has_a_test() -> None:
    assert sorted(set(spec.MODBUS) - set(COVERED)) == []
    assert sorted(set(COVERED) - set(spec.MODBUS)) == []
    assert len(spec.MODBUS) == 68  # 24 + 22 + 15 + 7
