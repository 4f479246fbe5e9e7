"""Navigation parameters (puwei-api §7): ``/api/param/get/:name`` and ``set/:name/:value``.

Each Puwei name is one runtime setting, converted at the edge (STYLE R13): ``ang_err`` is in
degrees on the wire and radians inside. A value is checked against the document's range first
(§7.2; A25: out of range is refused, nothing changes), then the runtime checks its own: where
the runtime's range is narrower than the document's (``pos_err`` above 0.25 m, ``ang_err``
above 57.3°: the controller cannot hold more) the runtime's refusal is the answer.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

from polynav.errors import InvalidRequest, NotFound
from polynav.protocols.puwei.context import Context
from polynav.protocols.puwei.endpoint import RouteList
from polynav.protocols.puwei.request import PuweiRequest, number

log = logging.getLogger(__name__)

ROUTES = RouteList()


@dataclass(frozen=True, slots=True)
class Parameter:
    """A Puwei parameter: its runtime setting, range on the wire and conversions."""

    setting: str
    low: float
    high: float
    unit: str
    to_wire: Callable[[float], float] = float
    from_wire: Callable[[float], float] = float


PARAMETERS: dict[str, Parameter] = {
    "max_vel": Parameter("max_linear_velocity", 0.1, 0.8, "m/s"),
    "pos_err": Parameter("xy_goal_tolerance", 0.05, 1.0, "m"),
    "ang_err": Parameter("yaw_goal_tolerance", 2.0, 180.0, "°", math.degrees, math.radians),
    "low_bat": Parameter("low_battery_percent", 10.0, 50.0, "%"),
    "full_bat": Parameter("full_battery_percent", 60.0, 100.0, "%"),
}


def parameter(name: str) -> Parameter:
    try:
        return PARAMETERS[name]
    except KeyError:
        raise NotFound("parameter", name) from None


def read(ctx: Context, name: str) -> float:
    """Parameter ``name`` in Puwei's unit."""
    spec = parameter(name)
    value = float(getattr(ctx.runtime.settings(), spec.setting))
    return round(spec.to_wire(value), 6)


@ROUTES.get("/api/param/get/:name", inline=True)
def get(ctx: Context, request: PuweiRequest) -> float:
    """``data``: the value (float) in Puwei's unit."""
    return read(ctx, request.name())


@ROUTES.get("/api/param/set/:name/:value")
def set_(ctx: Context, request: PuweiRequest) -> None:
    """Set ``name`` to ``value`` (Puwei's unit, within the document's range)."""
    name = request.name()
    spec = parameter(name)
    value = number(request.name("value"), "value")
    if not spec.low <= value <= spec.high:
        raise InvalidRequest("value", f"{name} must be {spec.low:g} to {spec.high:g} "
                                      f"{spec.unit}, got {value:g}")
    try:
        ctx.runtime.update_settings({spec.setting: spec.from_wire(value)})
    except InvalidRequest as exc:
        raise InvalidRequest("value", f"{name} {value:g} {spec.unit} refused by the robot: "
                                      f"{exc.reason}") from None
    log.info("puwei: %s set to %g %s", name, value, spec.unit)
