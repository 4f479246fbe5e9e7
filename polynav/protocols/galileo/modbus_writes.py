"""What a write to a Galileo Modbus coil or holding register does (spec galileo-wire-protocols
§3.3, §3.5), through the native control every Galileo wire shares.

Write semantics (``docs/decisions.md``, "Galileo Modbus"):

* A write acts each time it arrives, as the native command it stands for (§1.4): a command that
  is invalid in the robot's state is ignored, as on the serial line (the status tables show the
  result). Since "start" while started or "stop" while stopped is such a command, the switches
  behave as levels: writing back what a coil reads does nothing.
* A value the register has no meaning for (a coil 1 on a reserved or shutdown-only-1 coil is
  fine, but a goal index out of range, a pause word other than 0/1, a NaN coordinate, a dwell
  outside 0..255) refuses the whole request with exception 3 before anything is done.
* Multi-register values act when their high word is written: teleop (40002, 40004) at once with
  the other speed as in force; the goal pose when theta's high word (40013) is written, with x
  and y as last written. Words written before that wait (and read back as written), so a master
  that can only write one register at a time (FC 06) still sets a float or a pose.
* "1 = cancel" (40007) and "1 = shut down" (00003) act on each 1 written and read back 0.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from polynav.errors import PolynavError
from polynav.protocols.galileo import modbus_registers as regs
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.native.control import MAX_LOOP_WAIT, NativeControl, Outcome

log = logging.getLogger(__name__)


class IllegalValue(ValueError):
    """A written value the register has no meaning for (Modbus exception 3)."""


Action = Callable[[], object]


@dataclass
class ModbusState:
    """What the Modbus server(s) of one robot remember between requests.

    Attributes:
        words: holding words written but not acted on yet (a float's low word, x and y of a
            pose), by PDU address.
        teleop: the last teleop command written (linear, angular) and when [s, runtime clock].
    """

    words: dict[int, int] = field(default_factory=dict)
    teleop: tuple[float, float] = (0.0, 0.0)
    teleop_at: float = -math.inf
    lock: threading.Lock = field(default_factory=threading.Lock)

    def teleop_in_force(self, now: float, timeout: float) -> tuple[float, float]:
        """The last teleop command while it holds (the runtime's dead-man), else zeros."""
        with self.lock:
            return self.teleop if now < self.teleop_at + timeout else (0.0, 0.0)


def modbus_state(ctx: Context) -> ModbusState:
    """The Modbus state of ``ctx``'s robot."""
    return ctx.state("galileo.modbus", ModbusState)


def _run(name: str, command: Callable[[], Outcome]) -> bool:
    """Run a native command; like the serial line, an invalid one is ignored (logged).
    Returns whether it was carried out."""
    try:
        outcome = command()
    except PolynavError as exc:
        outcome = Outcome(False, str(exc))
    if outcome.accepted:
        log.info("galileo modbus: %s", name)
    else:
        log.info("galileo modbus: %s ignored: %s", name, outcome.reason)
    return outcome.accepted


def coil_actions(control: NativeControl, ctx: Context, address: int,
                 values: Sequence[bool]) -> list[Action]:
    """The actions of writing ``values`` to the coils from PDU ``address`` on, in address
    order; every value checked first.

    Raises:
        IllegalValue: a 1 on a reserved coil.
    """
    actions: list[Action] = []
    outputs: dict[int, int] = {}
    for offset, value in enumerate(values):
        coil = address + offset
        on = bool(value)
        if coil == regs.CO_NAVIGATION:
            actions.append(_command("navigation", on, control.start_navigation,
                                    control.stop_navigation))
        elif coil == regs.CO_MAPPING:
            actions.append(_command("mapping", on, control.start_mapping,
                                    control.stop_mapping))
        elif coil == regs.CO_SHUTDOWN:
            if on:
                actions.append(lambda: _run("shutdown", control.shutdown))
        elif coil == regs.CO_LOOP:
            actions.append(_command("loop", on, control.start_loop, control.stop_loop))
        elif coil == regs.CO_CHARGE:
            actions.append(_command("charge", on, control.start_charge, control.stop_charge))
        elif coil in regs.CO_RESERVED:
            if on:
                raise IllegalValue(f"coil {coil + 1} is reserved (reads and takes 0 only)")
        else:
            outputs[coil - regs.CO_VIRTUAL_IO] = int(on)
    if outputs:
        actions.append(lambda: _set_outputs(ctx, outputs))
    return actions


def _command(name: str, on: bool, start: Callable[[], Outcome],
             stop: Callable[[], Outcome]) -> Action:
    if on:
        return lambda: _run(f"start {name}", start)
    return lambda: _run(f"stop {name}", stop)


def _set_outputs(ctx: Context, outputs: dict[int, int]) -> None:
    """Virtual IO 8-15: the expansion board's outputs 0-7, all at once (or none: a robot
    powered off, a board with fewer outputs)."""
    try:
        ctx.runtime.peripherals.set_outputs("expansion_io", outputs)
    except PolynavError as exc:
        log.info("galileo modbus: expansion outputs %s ignored: %s", outputs, exc)
        return
    log.info("galileo modbus: expansion outputs %s", outputs)


def holding_actions(control: NativeControl, ctx: Context, image: list[int], address: int,
                    values: Sequence[int]) -> list[Action]:
    """The actions of writing ``values`` to the holding registers from PDU ``address`` on;
    every value checked first. ``image`` is what the table reads now (pending words included);
    the words that wait for their high word are kept pending (see the module's docstring).

    Raises:
        IllegalValue: see the module's docstring.
    """
    words = list(image)
    written = range(address, address + len(values))
    words[address:address + len(values)] = [int(v) & 0xFFFF for v in values]
    actions: list[Action] = []
    keep: dict[int, int] = {}

    if regs.HR_TELEOP_LINEAR + 1 in written or regs.HR_TELEOP_ANGULAR + 1 in written:
        linear = regs.words_float32(*words[regs.HR_TELEOP_LINEAR:regs.HR_TELEOP_LINEAR + 2])
        angular = regs.words_float32(*words[regs.HR_TELEOP_ANGULAR:regs.HR_TELEOP_ANGULAR + 2])
        if not (math.isfinite(linear) and math.isfinite(angular)):
            raise IllegalValue(f"teleop speeds must be finite, not ({linear}, {angular})")
        actions.append(lambda: _teleop(ctx, control, linear, angular))
    else:
        keep.update({a: words[a] for a in written if a < regs.HR_GOAL_INDEX})

    if regs.HR_GOAL_INDEX in written:
        index = regs.word_int16(words[regs.HR_GOAL_INDEX])
        _check_goal_index(control, index)
        actions.append(lambda: _run(f"go to goal {index}", lambda: control.go_to_goal(index)))

    if regs.HR_PAUSE in written:
        word = words[regs.HR_PAUSE]
        if word not in (0, 1):
            raise IllegalValue(f"40006 takes 1 (pause) or 0 (resume), not {word}")
        if word:
            actions.append(lambda: _run("pause", control.pause))
        else:
            actions.append(lambda: _run("resume", control.resume))

    if regs.HR_CANCEL in written:
        word = words[regs.HR_CANCEL]
        if word not in (0, 1):
            raise IllegalValue(f"40007 takes 1 (cancel) or 0, not {word}")
        if word:
            actions.append(lambda: _run("cancel", control.cancel))

    if regs.HR_GOAL_THETA + 1 in written:
        x, y, theta = (regs.words_float32(*words[a:a + 2])
                       for a in (regs.HR_GOAL_X, regs.HR_GOAL_Y, regs.HR_GOAL_THETA))
        if not all(math.isfinite(v) for v in (x, y, theta)):
            raise IllegalValue(f"the goal pose must be finite, not ({x}, {y}, {theta})")
        actions.append(lambda: _run(f"move to ({x:.3f}, {y:.3f}, {theta:.3f})",
                                    lambda: control.move_to(x, y, theta)))
    else:
        keep.update({a: words[a] for a in written
                     if regs.HR_GOAL_X <= a <= regs.HR_GOAL_THETA + 1})

    if regs.HR_LOOP_WAIT in written:
        wait = regs.word_int16(words[regs.HR_LOOP_WAIT])
        if not 0 <= wait <= MAX_LOOP_WAIT:
            raise IllegalValue(f"the loop wait is 0..{MAX_LOOP_WAIT} s, not {wait}")
        actions.append(lambda: _run(f"loop wait {wait} s", lambda: control.set_loop_wait(wait)))

    actions.insert(0, lambda: _keep_pending(ctx, written, keep))
    return actions


def _teleop(ctx: Context, control: NativeControl, linear: float, angular: float) -> None:
    name = f"teleop {linear:.3f} m/s {angular:.3f} rad/s"
    if _run(name, lambda: control.teleop_velocity(linear, angular)):
        state = modbus_state(ctx)
        with state.lock:
            state.teleop, state.teleop_at = (linear, angular), ctx.runtime.now()


def _keep_pending(ctx: Context, written: range, keep: dict[int, int]) -> None:
    """Pending words: those just written that wait for their high word; a group that acted
    forgets its pending words."""
    state = modbus_state(ctx)
    with state.lock:
        if regs.HR_TELEOP_LINEAR + 1 in written or regs.HR_TELEOP_ANGULAR + 1 in written:
            for a in range(regs.HR_TELEOP_LINEAR, regs.HR_GOAL_INDEX):
                state.words.pop(a, None)
        if regs.HR_GOAL_THETA + 1 in written:
            for a in range(regs.HR_GOAL_X, regs.HR_GOAL_THETA + 2):
                state.words.pop(a, None)
        state.words.update(keep)


def _check_goal_index(control: NativeControl, index: int) -> None:
    if index < 0:
        raise IllegalValue(f"a goal index is 0 or more, not {index}")
    try:
        count = control.goal_count()
    except PolynavError as exc:  # no map or path in use: the command is ignored anyway
        log.debug("galileo modbus: no goal count: %s", exc)
        return
    if index >= count:
        raise IllegalValue(f"goal {index} does not exist ({count} goals)")
