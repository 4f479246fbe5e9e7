"""/api/maps/{name}/paths: the paths drawn on a map, for the robot to follow.

A path is a route of the site store (:class:`~polynav.store.route_stops.RouteBook`), so the
dialects that speak of paths (Galileo's ``/navigation/path``) see the ones drawn here; the
synthesized ``default`` route, which is no drawing, is not listed.
"""

from __future__ import annotations

import logging
from typing import Annotated

from fastapi import APIRouter, Body, Path, Request, Response

from polynav.api.deps import MapNamePath, StoreDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.examples import examples, one
from polynav.api.schemas import Name
from polynav.api.schemas_console import PathIn, PathOut
from polynav.store.route_stops import RouteBook, StopRoute
from polynav.store.site_store import SiteStore

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/maps", tags=["maps"], responses=LOOKUP)

#: The examples draw, then delete, one path across the demo's floor1 (lobby to initial).
DEMO_PATH = "patrol"
PathNamePath = Annotated[Name, Path(description="the path's name",
                                    openapi_examples=one("a drawn path", DEMO_PATH))]
PathBody = Body(openapi_examples=examples(
    lobby_to_initial={"points": [[5.5, 12.5], [6.5, 10.5], [8.0, 8.5]]}))


def _book(request: Request, store: SiteStore) -> RouteBook:
    """The app's one RouteBook (its lock orders this API's path edits)."""
    book: RouteBook | None = getattr(request.app.state, "route_book", None)
    if book is None or book.store is not store:
        book = RouteBook(store)
        request.app.state.route_book = book
    return book


def _out(route: StopRoute) -> PathOut:
    return PathOut(name=route.name, map=route.map_name,
                   points=[[x, y] for x, y, _ in route.polyline])


@router.get("/{name}/paths", operation_id="list_paths", response_model=list[PathOut])
def list_paths(name: MapNamePath, request: Request, store: StoreDep) -> list[PathOut]:
    """The map's drawn paths, by name (404 unknown map)."""
    book = _book(request, store)
    routes = [book.route(name, n) for n in book.names(name)]
    return [_out(r) for r in routes if r.stored and r.polyline]


@router.put("/{name}/paths/{path}", operation_id="save_path", response_model=PathOut,
            responses=responses(BODY, STATE))
def save_path(name: MapNamePath, path: PathNamePath, request: Request, store: StoreDep,
              body: PathIn = PathBody) -> PathOut:
    """Draw path ``path`` on the map, or redraw it (its stops, if a dialect gave it some,
    stay)."""
    polyline = [(p[0], p[1], 0.0) for p in body.points]
    return _out(_book(request, store).save_polyline(name, path, polyline, None))


@router.delete("/{name}/paths/{path}", operation_id="delete_path", status_code=204,
               responses=responses(LOOKUP))
def delete_path(name: MapNamePath, path: PathNamePath, request: Request,
                store: StoreDep) -> Response:
    """Delete the path (with what a dialect attached to it: its stops' own points, its walls)
    (404 unknown map or path)."""
    _book(request, store).delete(name, path)
    return Response(status_code=204)
