"""What every Puwei handler gets: the robot's runtime, the login tokens, and the adapter's own
state (one value per key, made on first use).

The HTTP side (``http.py``, ``auth.py``) and the WebSocket side (``ws.py``) meet here only: the
WebSocket checks its ``token`` query parameter with :meth:`Tokens.valid`, the same tokens the
HTTP login hands out.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol, TypeVar

from polynav.runtime.robot_runtime import RobotRuntime

T = TypeVar("T")


class Tokens(Protocol):
    """The tokens the login gave out."""

    def valid(self, token: str | None) -> bool:
        """Whether ``token`` is one the login gave out and it has not expired."""
        ...


@dataclass
class Context:
    """One Puwei adapter around one runtime."""

    runtime: RobotRuntime
    tokens: Tokens
    _state: dict[str, Any] = field(default_factory=dict)
    _lock: threading.Lock = field(default_factory=threading.Lock)

    def state(self, key: str, make: Callable[[], T]) -> T:
        """The adapter's value for ``key``, made by ``make`` on first use."""
        with self._lock:
            if key not in self._state:
                self._state[key] = make()
            value: T = self._state[key]
            return value
