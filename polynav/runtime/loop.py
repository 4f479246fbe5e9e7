"""The runtime's loop: physics steps paced against wall time, and commands run between them.

The tick loop is the only writer of robot state, so adapters' commands must run *between*
steps. :class:`CommandLoop` owns that discipline: while its thread runs (:meth:`CommandLoop.start`)
a command is queued and the caller waits for the loop to run it at the start of the next physics
step; without the thread (tests, :meth:`CommandLoop.advance_until`) it runs at once under the
loop's lock. It knows nothing of robots: it is given the step to run and what to do after each
command (refresh the status) and on a failure (stop the robot).
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future
from typing import TypeVar

from polynav.errors import Conflict

log = logging.getLogger(__name__)

T = TypeVar("T")

_EPS = 1e-9


class CommandLoop:
    """Runs ``step`` every physics period, paced at ``speed`` × wall time, and commands between.

    Args:
        step: one physics step (control when due, then the simulator).
        now: the clock the steps advance [s].
        physics_period: simulated seconds per step; the pacing sleeps at most this long ahead.
        speed: simulated seconds per wall second; 0: no pacing, ``step`` waits for its own
            time (a real robot's backend).
        max_lag: falling further behind than this [s of wall time] gives up catching up.
        after_command: run under the lock after each command that succeeded (a status refresh,
            so that a read right after a command shows its effect).
        on_failure: run when a step raises, before the loop thread dies (brake the robot).
    """

    def __init__(
        self,
        *,
        step: Callable[[], None],
        now: Callable[[], float],
        physics_period: float,
        speed: float,
        max_lag: float,
        after_command: Callable[[], None],
        on_failure: Callable[[], None],
    ) -> None:
        self._step = step
        self._now = now
        self._physics_period = physics_period
        self._speed = speed
        self._max_lag = max_lag
        self._after_command = after_command
        self._on_failure = on_failure
        self.lock = threading.RLock()
        self._commands: queue.SimpleQueue[tuple[Callable[[], object], Future[object]]] = (
            queue.SimpleQueue()
        )
        self._queue_lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._stopping = threading.Event()
        self._wake = threading.Event()
        self._loop_done = False

    @property
    def running(self) -> bool:
        return self._thread is not None

    def advance_until(self, done: Callable[[], bool], timeout: float) -> bool:
        """Step until ``done()`` holds (checked every physics step) or ``timeout`` simulated
        seconds pass, as fast as the machine goes.

        Returns:
            Whether ``done()`` held.

        Raises:
            Conflict: the loop thread is running.
        """
        if self._thread is not None:
            raise Conflict("the runtime's loop thread is running: advance() is for tests only")
        end = self._now() + timeout
        while not done():
            if self._now() >= end - _EPS:
                return False
            with self.lock:
                self._step()
        return True

    def start(self) -> None:
        """Run the loop on a daemon thread.

        Raises:
            Conflict: it already runs.
        """
        with self._queue_lock:
            if self._thread is not None:
                raise Conflict("the runtime is already running")
            self._stopping.clear()
            self._wake.clear()
            self._loop_done = False
            self._thread = threading.Thread(target=self._run, name="polynav-runtime", daemon=True)
            self._thread.start()

    def stop(self) -> bool:
        """Stop the loop thread and wait for it; queued commands still run.

        Returns:
            Whether a thread was running (stopping twice is harmless).
        """
        with self._queue_lock:
            thread = self._thread
            if thread is None:
                return False
            self._stopping.set()
            self._wake.set()
        thread.join()
        with self._queue_lock:
            self._thread = None
        self._run_commands()
        return True

    def call(self, fn: Callable[[], T]) -> T:
        """Run a command between steps: on the loop thread when it runs, else here."""
        with self._queue_lock:
            thread = self._thread
            queued = (
                thread is not None
                and not self._loop_done
                and threading.current_thread() is not thread
            )
            if queued:
                future: Future[object] = Future()
                self._commands.put((fn, future))
                self._wake.set()
        if not queued:
            with self.lock:
                result = fn()
                self._after_command()
                return result
        return future.result()  # type: ignore[return-value]

    def _run(self) -> None:
        try:
            if self._speed > 0.0:
                self._run_paced()
            else:
                while not self._stopping.is_set():
                    self._run_commands()
                    with self.lock:
                        self._step()
        except Exception:
            log.exception("the runtime loop failed; the robot is stopped")
            self._on_failure()
            raise
        finally:
            with self._queue_lock:
                self._loop_done = True
            self._run_commands()  # whatever was queued runs now; later commands run directly

    def _run_paced(self) -> None:
        speed = self._speed
        period = self._physics_period
        wall0, sim0 = time.monotonic(), self._now()
        lagged = 0
        while not self._stopping.is_set():
            self._run_commands()
            target = sim0 + (time.monotonic() - wall0) * speed
            ahead = self._now() - target
            if ahead < 0.0:
                if -ahead / speed > self._max_lag:
                    lagged += 1
                    log.log(logging.WARNING if lagged == 1 else logging.DEBUG,
                            "runtime fell %.2f s (simulated) behind its pace at %gx; not "
                            "catching up (%d times so far)", -ahead, speed, lagged)
                    wall0, sim0 = time.monotonic(), self._now()
                with self.lock:
                    self._step()
            else:
                # Sleeping is the loop's job: the runtime owns the clock and the pace. A
                # command wakes the loop early so that it does not wait for the next step.
                self._wake.wait(min((ahead + period) / speed, 0.05))
                self._wake.clear()

    def _run_commands(self) -> None:
        while True:
            try:
                fn, future = self._commands.get_nowait()
            except queue.Empty:
                return
            if not future.set_running_or_notify_cancel():
                continue
            with self.lock:
                try:
                    result = fn()
                except BaseException as exc:  # handed to the caller, who re-raises it
                    future.set_exception(exc)
                    continue
                self._after_command()
                future.set_result(result)
