"""Galileo's navigation serial port (galileo-wire-protocols §1): command frames in, the 89-byte
status frame out at 30 Hz.

The line is a configured device (``/dev/ttyUSB0``, opened with pyserial at 115200 8N1), or, with
no device, a pseudo-terminal pair polynav opens: a host program opens the pty's path as it would
the robot's USB serial adapter. Status frames go out at :data:`STATUS_RATE` of the runtime's
clock (simulated time in simulation, so a test sees the same frames whatever the machine), from
the runtime's step through a small queue to a writer thread, so a slow or absent reader never
holds the robot up: frames the line cannot take are dropped, as on a serial line nobody reads.
"""

from __future__ import annotations

import contextlib
import logging
import os
import queue
import select
import termios
import threading
import tty
from collections.abc import Callable
from typing import Protocol

import serial

from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.diagnostics import diagnostics
from polynav.protocols.galileo.native.commands import FrameReader
from polynav.protocols.galileo.native.control import native_control
from polynav.protocols.galileo.native.status_frame import pack_status
from polynav.protocols.galileo.status import galileo_status
from polynav.runtime.step_hooks import every

log = logging.getLogger(__name__)

BAUD = 115200
#: Status frames per second of the runtime's clock (§1.3).
STATUS_RATE = 30.0
#: Status frames waiting for the writer (2 s of them); older ones are dropped first.
_QUEUE = 64
_READ_WAIT = 0.1  # [s] a read returns at least this often, so stop() is prompt


class _Line(Protocol):
    """The byte line under the link."""

    path: str

    def read(self) -> bytes: ...

    def write(self, data: bytes) -> None: ...

    def close(self) -> None: ...


class PtyLine:
    """A pseudo-terminal pair: polynav holds the master end; ``path`` is the end a host opens.

    The slave end is set raw at 115200 baud (no echo, no line editing) and kept open by polynav
    too, so the pair lives while host programs come and go.
    """

    def __init__(self) -> None:
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)
        attrs = termios.tcgetattr(self._slave)
        attrs[4] = attrs[5] = termios.B115200
        termios.tcsetattr(self._slave, termios.TCSANOW, attrs)
        os.set_blocking(self._master, False)
        self.path = os.ttyname(self._slave)

    def read(self) -> bytes:
        ready, _, _ = select.select([self._master], [], [], _READ_WAIT)
        if not ready:
            return b""
        try:
            return os.read(self._master, 4096)
        except (BlockingIOError, InterruptedError):
            return b""

    def write(self, data: bytes) -> None:
        try:
            os.write(self._master, data)
        except BlockingIOError:
            log.debug("galileo serial: the pty is full (nobody reads), a frame is dropped")

    def close(self) -> None:
        for fd in (self._master, self._slave):
            with contextlib.suppress(OSError):
                os.close(fd)


class DeviceLine:
    """A serial device through pyserial, 115200 8N1, no flow control."""

    def __init__(self, path: str) -> None:
        self.path = path
        self._port = serial.Serial(path, BAUD, bytesize=serial.EIGHTBITS,
                                   parity=serial.PARITY_NONE, stopbits=serial.STOPBITS_ONE,
                                   timeout=_READ_WAIT, write_timeout=1.0)

    def read(self) -> bytes:
        waiting = max(1, self._port.in_waiting)
        return bytes(self._port.read(waiting))

    def write(self, data: bytes) -> None:
        try:
            self._port.write(data)
        except serial.SerialTimeoutException:
            log.debug("galileo serial: the line did not take a frame in time; dropped")

    def close(self) -> None:
        self._port.close()


class SerialLink:
    """The serial protocol on one line for one Galileo robot.

    Args:
        ctx: the Galileo context (its native control and status).
        device: a serial device path, or ``None`` for a new pseudo-terminal.
    """

    def __init__(self, ctx: Context, device: str | None = None) -> None:
        self._ctx = ctx
        self._line: _Line = PtyLine() if device is None else DeviceLine(device)
        self._frames: queue.Queue[bytes | None] = queue.Queue(_QUEUE)
        self._reader = FrameReader()
        self._stopping = threading.Event()
        self._threads: list[threading.Thread] = []
        self._detach: Callable[[], None] | None = None
        self._time_stamp = 0
        self.commands = 0  # command frames received and run

    @property
    def path(self) -> str:
        """The line's path: the device, or the pty a host opens."""
        return self._line.path

    def start(self) -> SerialLink:
        self._detach = every(self._ctx.runtime, 1.0 / STATUS_RATE,
                             lambda: self._queue(self._status_frame()))
        for name, target in (("read", self._read_loop), ("write", self._write_loop)):
            thread = threading.Thread(target=target, name=f"galileo-serial-{name}",
                                      daemon=True)
            thread.start()
            self._threads.append(thread)
        log.info("galileo serial on %s (%d 8N1)", self.path, BAUD)
        return self

    def stop(self) -> None:
        if self._detach is not None:
            self._detach()
            self._detach = None
        self._stopping.set()
        self._queue(None)
        for thread in self._threads:
            thread.join(timeout=2.0)
        self._threads.clear()
        self._line.close()

    def _status_frame(self) -> bytes:
        self._time_stamp += 1
        return pack_status(galileo_status(self._ctx), self._time_stamp)

    def _queue(self, frame: bytes | None) -> None:
        while True:
            try:
                self._frames.put_nowait(frame)
                return
            except queue.Full:
                with contextlib.suppress(queue.Empty):
                    self._frames.get_nowait()

    def _write_loop(self) -> None:
        while True:
            frame = self._frames.get()
            if frame is None or self._stopping.is_set():
                return
            try:
                self._line.write(frame)
            except OSError as exc:
                log.warning("galileo serial: writing to %s failed: %s", self.path, exc)

    def _read_loop(self) -> None:
        control = native_control(self._ctx)
        counters = diagnostics(self._ctx)
        reader = self._reader
        while not self._stopping.is_set():
            try:
                data = self._line.read()
            except (OSError, serial.SerialException) as exc:
                if self._stopping.is_set():
                    return
                log.warning("galileo serial: reading %s failed: %s", self.path, exc)
                self._stopping.wait(_READ_WAIT)
                continue
            skipped, dropped = reader.skipped, reader.dropped
            payloads = reader.feed(data)
            counters.count("serial.garbage_bytes", reader.skipped - skipped)
            counters.count("serial.bad_length", reader.dropped - dropped)
            for payload in payloads:
                control.apply(payload)
                self.commands += 1
