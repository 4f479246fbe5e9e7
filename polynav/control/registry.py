"""Controllers by name, so configuration picks one without ``isinstance`` chains (STYLE R2)."""

from __future__ import annotations

from collections.abc import Callable

from polynav.control.interface import Controller
from polynav.control.pure_pursuit import RegulatedPurePursuit

CONTROLLERS: dict[str, Callable[[], Controller]] = {
    "regulated_pure_pursuit": RegulatedPurePursuit,
}
