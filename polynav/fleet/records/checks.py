"""Checks of what the fleet records are given, before anything is written: a bad value is an
:class:`~polynav.errors.InvalidRequest` naming its field, never a half-done transaction."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from typing import Any

from polynav.errors import InvalidRequest
from polynav.fleet.records import schema as s


def check_order(order_id: str, update_id: int, robot: str, mission: str | None) -> None:
    """One sent order update's fields, checked before anything is written."""
    check_name("order_id", order_id)
    check_name("robot", robot)
    if mission is not None:
        check_name("mission", mission)
    if isinstance(update_id, bool) or not isinstance(update_id, int) or update_id < 0:
        raise InvalidRequest("update_id", f"must be an integer >= 0, got {update_id!r}")


def check_name(field: str, value: object) -> None:
    if not isinstance(value, str) or not value.strip():
        raise InvalidRequest(field, f"must be a non-empty name, got {value!r}")
    if len(value) > s.NAME:
        raise InvalidRequest(field, f"longer than {s.NAME} characters")


def check_time(value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value):
        raise InvalidRequest("now", f"must be a finite time in seconds, got {value!r}")
    return float(value)


def check_duration(value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value) or value <= 0.0:
        raise InvalidRequest("duration", f"must be > 0 s, got {value!r}")
    return float(value)


def check_json(field: str, value: object) -> None:
    try:
        json.dumps(value, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise InvalidRequest(field, f"not JSON: {exc}") from exc


def check_stops(stops: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """The stops as a list of plain JSON objects, each naming its point."""
    if isinstance(stops, (str, bytes)) or not isinstance(stops, Sequence) or not stops:
        raise InvalidRequest("stops", "a mission needs a list of at least one stop")
    out = []
    for k, stop in enumerate(stops):
        if not isinstance(stop, Mapping):
            raise InvalidRequest(f"stops[{k}]", f"must be an object, got {stop!r}")
        point = stop.get("point")
        if not isinstance(point, str) or not point.strip():
            raise InvalidRequest(f"stops[{k}].point", f"must be a non-empty name, got {point!r}")
        out.append(dict(stop))
    check_json("stops", out)
    # As the database gives it back (JSON round trip), so a repeated add compares equal.
    loaded: list[dict[str, Any]] = json.loads(json.dumps(out))
    return loaded
