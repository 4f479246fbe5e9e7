"""What a Puwei route module declares: :class:`Endpoint` entries in a :class:`RouteList`.

Each route module (``launch.py``, ``maps.py``, ``params.py`` ...) owns one ``ROUTES =
RouteList()`` and decorates its handlers with the path as the vendor's document writes it
(``/api/map/delete/:name`` becomes Starlette's ``/api/map/delete/{name}``). A handler converts
units and terms, calls one runtime command (or reads the snapshot or the store) and returns the
envelope's ``data`` (JSON-ready), or a Starlette ``Response`` for a file. polynav exceptions
propagate; the HTTP layer wraps both in the envelope (:mod:`polynav.protocols.puwei.errors`).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from polynav.protocols.puwei.context import Context
    from polynav.protocols.puwei.request import PuweiRequest

Handler = Callable[["Context", "PuweiRequest"], Any]

_PARAM = re.compile(r":([a-z_]+)")


def starlette_path(path: str) -> str:
    """``/api/map/delete/:name`` -> ``/api/map/delete/{name}``."""
    return _PARAM.sub(r"{\1}", path)


@dataclass(frozen=True, slots=True)
class Endpoint:
    """One method + path of the API.

    Attributes:
        method: ``GET`` or ``POST``.
        path: the vendor's path (``/api/map/delete/:name``).
        handler: builds the reply's ``data`` (or a file response).
        inline: the handler only reads the status snapshot or in-memory state and runs on the
            event loop; others run on a worker thread (runtime commands wait for its loop).
        public: served without the ``authorization`` header (login and device discovery,
            puwei-api §2.2).
    """

    method: str
    path: str
    handler: Handler
    inline: bool = False
    public: bool = False


class RouteList:
    """The endpoints of one route module, in declaration order."""

    def __init__(self) -> None:
        self._endpoints: list[Endpoint] = []

    def __iter__(self) -> Iterator[Endpoint]:
        return iter(self._endpoints)

    def add(self, method: str, path: str, *, inline: bool = False, public: bool = False
            ) -> Callable[[Handler], Handler]:
        """A decorator registering a handler for ``method`` on ``path``."""

        def register(handler: Handler) -> Handler:
            self._endpoints.append(Endpoint(method, path, handler, inline, public))
            return handler

        return register

    def get(self, path: str, **options: Any) -> Callable[[Handler], Handler]:
        return self.add("GET", path, **options)

    def post(self, path: str, **options: Any) -> Callable[[Handler], Handler]:
        return self.add("POST", path, **options)
