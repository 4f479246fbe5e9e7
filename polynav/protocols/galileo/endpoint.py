"""What a Galileo route module declares: :class:`Endpoint` entries in a :class:`RouteList`.

Each route module (``maps.py``, ``navigation.py``, ``status.py`` ...) owns one ``ROUTES =
RouteList()`` and decorates its handlers::

    @ROUTES.get("/navigation/pose", inline=True)
    def pose(ctx: Context, params: Params) -> Reply: ...

Paths are written as the vendor's document writes them (without ``/api/v1``); the list adds the
prefix. :mod:`polynav.protocols.galileo.routes` gathers every module's list, so a new module is
added there by one line. A handler converts units and terms, calls one runtime command (or reads
the snapshot or the store) and returns the vendor reply: a JSON-ready ``dict``/``list``
(``None``: JSON ``null``), or a Starlette ``Response`` for files. polynav exceptions
propagate; the HTTP layer maps them (:mod:`polynav.protocols.galileo.errors`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from starlette.responses import Response

if TYPE_CHECKING:
    from polynav.protocols.galileo.context import Context
    from polynav.protocols.galileo.params import Params

PREFIX = "/api/v1"

Reply = dict[str, Any] | list[Any] | Response | None
Handler = Callable[["Context", "Params"], Reply]


@dataclass(frozen=True, slots=True)
class Endpoint:
    """One method + path of the API.

    Attributes:
        method: ``GET``, ``POST``, ``PUT`` or ``DELETE``.
        path: the full URL path (``/api/v1/...``).
        handler: builds the reply.
        inline: the handler only reads the prebuilt status snapshot or in-memory state and is
            answered on the event loop; others run on a worker thread (runtime commands wait
            for the runtime's loop, store reads touch the disk).
        result_errors: the documented reply has ``result: bool``, so a refused request is
            answered ``{"result": false, "description": ...}`` rather than an HTTP error
            (spec galileo-http-b §2, "Errors").
        public: served without a token (only ``/token``).
    """

    method: str
    path: str
    handler: Handler
    inline: bool = False
    result_errors: bool = False
    public: bool = False


class RouteList:
    """The endpoints of one route module, in declaration order."""

    def __init__(self) -> None:
        self._endpoints: list[Endpoint] = []

    def __iter__(self) -> Iterator[Endpoint]:
        return iter(self._endpoints)

    def __len__(self) -> int:
        return len(self._endpoints)

    def add(
        self,
        method: str,
        path: str,
        *,
        inline: bool = False,
        result_errors: bool = False,
        public: bool = False,
        prefix: str = PREFIX,
    ) -> Callable[[Handler], Handler]:
        """A decorator registering a handler for ``method`` on ``prefix + path``."""

        def register(handler: Handler) -> Handler:
            self._endpoints.append(
                Endpoint(method, prefix + path, handler, inline, result_errors, public)
            )
            return handler

        return register

    def get(self, path: str, **options: Any) -> Callable[[Handler], Handler]:
        return self.add("GET", path, **options)

    def post(self, path: str, **options: Any) -> Callable[[Handler], Handler]:
        return self.add("POST", path, **options)

    def put(self, path: str, **options: Any) -> Callable[[Handler], Handler]:
        return self.add("PUT", path, **options)

    def delete(self, path: str, **options: Any) -> Callable[[Handler], Handler]:
        return self.add("DELETE", path, **options)
