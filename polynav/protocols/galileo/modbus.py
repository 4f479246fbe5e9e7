"""The Galileo Modbus TCP server (spec galileo-wire-protocols §3; default port 3551).

Transport only: pymodbus's asyncio TCP server on the Galileo servers' event loop, over a
datastore that has no memory of its own: every read builds the tables from the runtime at that
instant (:mod:`~polynav.protocols.galileo.modbus_registers`), every write becomes native commands
(:mod:`~polynav.protocols.galileo.modbus_writes`). Runtime calls run in a worker thread, so a
slow one never stalls the other connections.

Any unit id is answered (the document names none, A7). Reads outside the map get exception 2
(illegal data address), as do writes outside it; a value the register has no meaning for gets
exception 3 (illegal data value), and nothing of that request is done. Discrete inputs and
input registers have no write function in Modbus, so they cannot be written at all.
"""

from __future__ import annotations

import asyncio
import logging
import threading
import weakref
from collections.abc import Sequence
from typing import Any

import numpy as np
from pymodbus.constants import ExcCodes
from pymodbus.datastore import ModbusServerContext
from pymodbus.server import ModbusTcpServer

from polynav.errors import PolynavError
from polynav.protocols.galileo import modbus_registers as regs
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.diagnostics import diagnostics
from polynav.protocols.galileo.modbus_writes import (
    IllegalValue,
    coil_actions,
    holding_actions,
    modbus_state,
)
from polynav.protocols.galileo.native.control import native_control
from polynav.protocols.galileo.status import galileo_status

log = logging.getLogger(__name__)

# Function code -> table (pymodbus routes every request through these codes).
_DISCRETE_INPUTS, _COILS, _INPUT_REGISTERS, _HOLDING = "d", "c", "i", "h"
_TABLES = {1: _COILS, 5: _COILS, 15: _COILS, 2: _DISCRETE_INPUTS, 4: _INPUT_REGISTERS,
           3: _HOLDING, 6: _HOLDING, 16: _HOLDING, 22: _HOLDING, 23: _HOLDING}
_SIZES = {_DISCRETE_INPUTS: regs.DISCRETE_INPUTS, _COILS: regs.COILS,
          _INPUT_REGISTERS: regs.INPUT_REGISTERS, _HOLDING: regs.HOLDING_REGISTERS}
#: Single writes, whose reply echoes the value written.
_SINGLE_WRITES = (5, 6)


def reading(ctx: Context, *, scan: bool = True) -> regs.Reading:
    """The robot now, as the register map shows it (tracked points 0 without ``scan``: only
    the input registers show them)."""
    runtime = ctx.runtime
    outputs, inputs = expansion_io(ctx)  # first: a runtime command refreshes the snapshot
    snap = runtime.status()
    status = galileo_status(ctx, snap)
    return regs.Reading(
        status=status,
        tracked_points=tracked_points(ctx, status["visualStatus"]) if scan else 0,
        io_inputs=inputs,
        io_outputs=outputs,
        teleop=modbus_state(ctx).teleop_in_force(runtime.now(), runtime.config.teleop_timeout),
        goal=snap.goal,
        loop_wait=native_control(ctx).loop_wait,
    )


def expansion_io(ctx: Context) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """The expansion board's (outputs, inputs): virtual IO 8-15 and 0-7; all 0 while the robot
    is powered off."""
    try:
        outputs, inputs = ctx.runtime.peripherals.io_state("expansion_io")
    except PolynavError as exc:
        log.debug("galileo modbus: no IO: %s", exc)
        return (), ()
    return tuple(int(v or 0) for v in outputs), tuple(int(v) for v in inputs)


def tracked_points(ctx: Context, visual: int) -> int:
    """The scan returns localization matches while it tracks (``visualStatus`` 1), else 0: the
    lidar's counterpart of the visual system's tracked feature points."""
    if visual != 1:
        return 0
    runtime = ctx.runtime
    try:
        scan = runtime.run_between_ticks(runtime.robot.read_scan)
    except PolynavError as exc:
        log.debug("galileo modbus: no scan: %s", exc)
        return 0
    if scan is None:
        return 0
    ranges = scan.ranges
    valid = np.isfinite(ranges) & (ranges >= scan.range_min) & (ranges <= scan.range_max)
    return int(np.count_nonzero(valid))


class GalileoDatastore(ModbusServerContext):
    """The four tables of one robot, computed on each request.

    A :class:`ModbusServerContext` for pymodbus's server to accept it; nothing of the base's
    device store is used (its ``__init__`` is not called: it needs device blocks this
    datastore has not).
    """

    def __init__(self, ctx: Context) -> None:
        self._ctx = ctx
        # What pymodbus's server reads from a context it uses as is.
        self.old_simulator = True
        self.simdevices = []
        # The value a single write (FC 05/06) wrote, for its reply's echo: pymodbus reads the
        # register back for it, and a switch reads its state, not what was written.
        self._echo: weakref.WeakKeyDictionary[asyncio.Task[Any], list[int] | list[bool]] = (
            weakref.WeakKeyDictionary())
        # One write at a time: a write reads the holding image, then acts on it.
        self._writing = threading.Lock()

    def device_ids(self) -> list[int]:
        """Every unit id reaches the one robot."""
        return [0]

    async def async_getValues(
        self, device_id: int, func_code: int, address: int, count: int = 1
    ) -> list[int] | list[bool] | ExcCodes:
        """``count`` values of the table ``func_code`` reads, from PDU ``address``; an
        exception answer is counted (``modbus.read_exception_<code>``)."""
        result = await self._get_values(func_code, address, count)
        if isinstance(result, ExcCodes):
            diagnostics(self._ctx).count(f"modbus.read_exception_{int(result)}")
        return result

    async def async_setValues(
        self, device_id: int, func_code: int, address: int,
        values: Sequence[int] | Sequence[bool],
    ) -> ExcCodes | None:
        """Write ``values`` from PDU ``address`` of the table ``func_code`` writes; an
        exception answer is counted (``modbus.write_exception_<code>``)."""
        result = await self._set_values(func_code, address, values)
        if result is not None:
            diagnostics(self._ctx).count(f"modbus.write_exception_{int(result)}")
        return result

    async def _get_values(
        self, func_code: int, address: int, count: int
    ) -> list[int] | list[bool] | ExcCodes:
        task = asyncio.current_task()
        if func_code in _SINGLE_WRITES and task is not None and task in self._echo:
            return self._echo.pop(task)
        table = _TABLES.get(func_code)
        if table is None:
            return ExcCodes.ILLEGAL_FUNCTION
        if count < 1:
            return ExcCodes.ILLEGAL_VALUE
        if address < 0 or address + count > _SIZES[table]:
            return ExcCodes.ILLEGAL_ADDRESS
        values = await asyncio.to_thread(self._read, table)
        return values[address:address + count]

    async def _set_values(
        self, func_code: int, address: int, values: Sequence[int] | Sequence[bool],
    ) -> ExcCodes | None:
        table = _TABLES.get(func_code)
        if table not in (_COILS, _HOLDING):
            return ExcCodes.ILLEGAL_FUNCTION
        if not values:
            return ExcCodes.ILLEGAL_VALUE
        if address < 0 or address + len(values) > _SIZES[table]:
            return ExcCodes.ILLEGAL_ADDRESS
        try:
            await asyncio.to_thread(self._write, table, address, list(values))
        except IllegalValue as exc:
            log.info("galileo modbus: refused a write at %d: %s", address, exc)
            return ExcCodes.ILLEGAL_VALUE
        task = asyncio.current_task()
        if func_code in _SINGLE_WRITES and task is not None:
            self._echo[task] = list(values)
        return None

    def _read(self, table: str) -> list[int] | list[bool]:
        r = reading(self._ctx, scan=table == _INPUT_REGISTERS)
        if table == _DISCRETE_INPUTS:
            return regs.discrete_inputs(r)
        if table == _COILS:
            return regs.coils(r)
        if table == _INPUT_REGISTERS:
            return regs.input_registers(r)
        return self._holding(r)

    def _holding(self, r: regs.Reading) -> list[int]:
        words = regs.holding_registers(r)
        state = modbus_state(self._ctx)
        with state.lock:
            for address, word in state.words.items():
                words[address] = word
        return words

    def _write(self, table: str, address: int, values: list[int] | list[bool]) -> None:
        control = native_control(self._ctx)
        with self._writing:
            if table == _COILS:
                actions = coil_actions(control, self._ctx, address, [bool(v) for v in values])
            else:
                image = self._holding(reading(self._ctx, scan=False))
                actions = holding_actions(control, self._ctx, image, address,
                                          [int(v) for v in values])
            for action in actions:
                action()


class ModbusListener:
    """pymodbus's TCP server on ``host``:``port`` (0: any free port) over the robot's
    datastore; :meth:`start` and :meth:`close` on the loop it serves on."""

    def __init__(self, ctx: Context, host: str, port: int) -> None:
        self._ctx = ctx
        self._host = host
        self._requested_port = port
        self._server: ModbusTcpServer | None = None
        self.port = port

    async def start(self) -> None:
        """Listen (raises OSError when the port is taken)."""
        server = ModbusTcpServer(GalileoDatastore(self._ctx),
                                 address=(self._host, self._requested_port))
        try:
            await server.serve_forever(background=True)
        except RuntimeError as exc:  # pymodbus's word for a failed listen
            raise OSError(f"galileo modbus: cannot listen on {self._host}:"
                          f"{self._requested_port}") from exc
        self._server = server
        sockets = server.transport.sockets  # type: ignore[attr-defined]
        self.port = int(sockets[0].getsockname()[1])

    async def close(self) -> None:
        """Stop listening and drop the clients."""
        if self._server is not None:
            await self._server.shutdown()  # type: ignore[no-untyped-call]
            self._server = None
