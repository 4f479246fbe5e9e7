"""The root of polynav's exceptions.

Each package keeps its own failures beside its code (``planning/errors.py`` and so on), all derived
from :class:`PolynavError`, so that a dialect adapter can map any of them to its vendor's error with
one lookup along the exception's MRO.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import TypeVar

_V = TypeVar("_V")


class PolynavError(Exception):
    """Base of every error polynav raises on purpose."""


class ConfigError(PolynavError, ValueError):
    """A configuration value is out of range or conflicts with another; names the full key."""

    def __init__(self, key: str, reason: str) -> None:
        super().__init__(f"{key}: {reason}")
        self.key = key
        self.reason = reason


def check_positive(config: object, prefix: str, names: Iterable[str]) -> None:
    """Raise :class:`ConfigError` (key ``prefix + name``) for the first of ``config``'s
    attributes ``names`` that is not a finite number > 0: the check every timing and distance
    of a configuration dataclass needs in its ``__post_init__``."""
    for name in names:
        value = getattr(config, name)
        if not (math.isfinite(value) and value > 0.0):
            raise ConfigError(prefix + name, f"must be finite and > 0, got {value}")


class InvalidRequest(PolynavError, ValueError):
    """A request from outside is malformed or names something unknown."""

    def __init__(self, field: str, reason: str) -> None:
        super().__init__(f"{field}: {reason}")
        self.field = field
        self.reason = reason


class StorageError(PolynavError):
    """Reading or writing site data failed."""


class NotFound(PolynavError, KeyError):
    """A named thing (map, point, floor, setting) does not exist."""

    def __init__(self, kind: str, name: str) -> None:
        super().__init__(f"{kind} {name!r} not found")
        self.kind = kind
        self.name = name

    def __str__(self) -> str:
        return str(self.args[0])


def look_up(table: Mapping[str, _V], kind: str, name: str) -> _V:
    """``table[name]``: the one way a by-name lookup fails (a door, a lift car, a schedule).

    Raises:
        NotFound: ``name`` is not in ``table``; the error names ``kind``.
    """
    found = table.get(name)
    if found is None:
        raise NotFound(kind, name)
    return found


class Conflict(PolynavError):
    """The command is valid but not in the robot's current state (wrong mode, already running)."""


class NotLocalized(Conflict):
    """The robot's pose could not be told from its scan (no match on the map, or several)."""
