"""The blackboard: one dictionary of values shared by every node of a task tree.

Given at the root when the task is made (galileo-tasks-bt-ws §7.6) and written by actions as
they end (each action type documents the keys it writes, ``nav.x``, ``image.file``...). A
string parameter holding ``{key}`` is filled in when its node starts, not when the tree is
made, so a node sees what earlier nodes wrote: a parameter that is exactly ``"{key}"`` takes
the value with its JSON type, ``{key}`` inside longer text becomes the value as text, and a key
the blackboard does not hold is left as written (the document's rule for unknown names). The
stored parameters never change: a task read back still shows ``"{key}"``.
"""

from __future__ import annotations

import json
import re
from collections.abc import Mapping
from typing import Any

from polynav.errors import InvalidRequest

#: A key: a name, with dots for the keys actions write (``nav.x``).
KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*")
_PLACEHOLDER = re.compile(r"\{(" + KEY.pattern + r")\}")
MAX_KEYS = 1000
MAX_TEXT = 65_536  # [characters] of a value written as text into a parameter


def check_key(key: object, field: str = "blackboard") -> str:
    """``key`` if it is a blackboard key.

    Raises:
        InvalidRequest: not a string of names joined by dots.
    """
    if not isinstance(key, str) or KEY.fullmatch(key) is None:
        raise InvalidRequest(field, f"{key!r} is no blackboard key (a name, or names joined by "
                                    "dots: letters, digits and '_', not starting with a digit)")
    return key


def placeholders(value: object) -> set[str]:
    """The keys ``{key}`` names anywhere in ``value`` (strings, lists, objects)."""
    found: set[str] = set()
    if isinstance(value, str):
        found.update(_PLACEHOLDER.findall(value))
    elif isinstance(value, Mapping):
        for item in value.values():
            found |= placeholders(item)
    elif isinstance(value, list | tuple):
        for item in value:
            found |= placeholders(item)
    return found


def is_placeholder(value: object) -> bool:
    """Whether ``value`` is exactly one ``{key}`` (its type is known only when it starts)."""
    return isinstance(value, str) and _PLACEHOLDER.fullmatch(value) is not None


class Blackboard:
    """The values of one task tree; read and written between ticks only."""

    def __init__(self, values: Mapping[str, Any] | None = None) -> None:
        if values is not None and not isinstance(values, Mapping):
            raise InvalidRequest("blackboard", "must be an object of key: value")
        self._values: dict[str, Any] = {}
        for key, value in (values or {}).items():
            self.write(key, value)

    def __contains__(self, key: object) -> bool:
        return key in self._values

    def read(self, key: str, default: Any = None) -> Any:
        return self._values.get(key, default)

    def write(self, key: str, value: Any) -> None:
        """Set ``key``.

        Raises:
            InvalidRequest: a bad key, a value that is not JSON, or a full blackboard.
        """
        check_key(key)
        try:
            json.dumps(value)
        except (TypeError, ValueError) as exc:
            raise InvalidRequest("blackboard", f"{key}: not a JSON value ({exc})") from None
        if key not in self._values and len(self._values) >= MAX_KEYS:
            raise InvalidRequest("blackboard", f"holds at most {MAX_KEYS} keys")
        self._values[key] = value

    def values(self) -> dict[str, Any]:
        return dict(self._values)

    def fill(self, value: Any) -> Any:
        """``value`` with every ``{key}`` the blackboard holds filled in (module docstring)."""
        if isinstance(value, str):
            whole = _PLACEHOLDER.fullmatch(value)
            if whole is not None:
                return self._values.get(whole.group(1), value)
            return _PLACEHOLDER.sub(self._as_text, value)
        if isinstance(value, Mapping):
            return {k: self.fill(v) for k, v in value.items()}
        if isinstance(value, list | tuple):
            return [self.fill(v) for v in value]
        return value

    def _as_text(self, match: re.Match[str]) -> str:
        key = match.group(1)
        if key not in self._values:
            return match.group(0)
        value = self._values[key]
        text = value if isinstance(value, str) else json.dumps(value, ensure_ascii=False)
        return text[:MAX_TEXT]
