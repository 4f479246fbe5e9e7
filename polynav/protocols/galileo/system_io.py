"""IO endpoints: the base's outputs, the IO expansion board and the voice module's IO, PWM and
servo (galileo-http-a §3.6, §3.10: E-24–E-27, E-45–E-48).

Documented types are kept on output (A-17): the base's ports as strings (``out1`` =
``"-1"`` unset / ``"0"`` / ``"1"``), the expansion board as ints, the voice module as bools keyed
by the program's port numbers (outputs ``0``–``3``, inputs ``4``–``7``, A-27). On input both
strings and numbers are accepted. A voice-module PUT sets all listed outputs or none.
"""

from __future__ import annotations

from typing import Any

from polynav.errors import InvalidRequest
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.system_replies import OK

ROUTES = RouteList()


def _level(params: Params) -> int:
    level = params.integer("level")
    if level not in (0, 1):
        raise InvalidRequest("level", f"must be 0 or 1, got {level}")
    return int(level)


@ROUTES.get("/system/io")
def get_io(ctx: Context, params: Params) -> Reply:
    """E-24: ``{"status": "ok", "out1": "-1"|"0"|"1", ...}``."""
    outputs, _ = ctx.runtime.peripherals.io_state("io")
    body: dict[str, Any] = {"status": OK}
    for k, level in enumerate(outputs, start=1):
        body[f"out{k}"] = "-1" if level is None else str(level)
    return body


@ROUTES.post("/system/io")
def post_io(ctx: Context, params: Params) -> Reply:
    """E-25: set output ``port`` ("1".."3") to ``level`` ("0"/"1")."""
    port, level = params.integer("port"), _level(params)
    ctx.runtime.peripherals.set_outputs("io", {port: level})
    return {"status": OK}


@ROUTES.get("/system/bw_io")
def get_bw_io(ctx: Context, params: Params) -> Reply:
    """E-26: the expansion board's 8 inputs and 8 outputs."""
    outputs, inputs = ctx.runtime.peripherals.io_state("expansion_io")
    return {"in": {str(k): int(v) for k, v in enumerate(inputs)},
            "out": {str(k): int(v or 0) for k, v in enumerate(outputs)}}


@ROUTES.put("/system/bw_io")
def put_bw_io(ctx: Context, params: Params) -> Reply:
    """E-27: set output ``port`` (0..7) to ``level``."""
    port, level = params.integer("port"), _level(params)
    ctx.runtime.peripherals.set_outputs("expansion_io", {port: level})
    return {"status": OK}


@ROUTES.get("/system/asr/io")
def get_asr_io(ctx: Context, params: Params) -> Reply:
    """E-45: the voice module's inputs 4..7 as bools."""
    _, inputs = ctx.runtime.peripherals.io_state("voice_io")
    return {str(4 + k): bool(v) for k, v in enumerate(inputs)}


@ROUTES.put("/system/asr/io")
def put_asr_io(ctx: Context, params: Params) -> Reply:
    """E-46: body ``{"0": true, ...}``: set the listed outputs (0..3), all or none."""
    levels: dict[int, int] = {}
    for key, value in params.values.items():
        if key == "token":
            continue
        try:
            port = int(key)
        except ValueError:
            raise InvalidRequest(key, "keys are output ports 0..3") from None
        levels[port] = int(Params({key: value}).boolean(key))
    if not levels:
        raise InvalidRequest("body", "give at least one port: {\"0\": true, ...}")
    ctx.runtime.peripherals.set_outputs("voice_io", levels)
    return {"status": OK}


@ROUTES.get("/system/asr/pwm")
def get_asr_pwm(ctx: Context, params: Params) -> Reply:
    """E-47: PWM of ``freq`` Hz and ``percent`` duty on output ``port``."""
    ctx.runtime.peripherals.set_pwm("voice_io", params.integer("port"),
                                    params.integer("freq"), params.integer("percent"))
    return {"status": OK}


@ROUTES.get("/system/asr/servo")
def get_asr_servo(ctx: Context, params: Params) -> Reply:
    """E-48: a servo signal for ``angle`` degrees on output ``port``."""
    ctx.runtime.peripherals.set_servo("voice_io", params.integer("port"),
                                      params.integer("angle"))
    return {"status": OK}
