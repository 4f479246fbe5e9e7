"""Bodies of the routes the web console draws from: the live scene and the map's keepouts.

Keepouts travel as a list of shapes told apart by ``kind`` (``wall``, ``zone``, ``circle``,
``guided``), the four shapes of :mod:`polynav.maps.keepout`, in world coordinates [m]; a list
read with GET can be written back with PUT unchanged, which is how the console undoes an edit.
"""

from __future__ import annotations

import logging
from typing import Annotated, Literal

from pydantic import BaseModel, Field

from polynav.api.schemas import Coordinate, PoseOut
from polynav.maps.keepout import CircleZone, ForbiddenZone, GuidedZone, Keepout, VirtualWall

log = logging.getLogger(__name__)

#: Most vertices in one shape, and most shapes on one map: bounds on what one request costs.
MAX_VERTICES = 1000
MAX_KEEPOUTS = 500

Vertex = Annotated[list[Coordinate], Field(min_length=2, max_length=2,
                                           description="(x, y) [m], world frame")]
Length = Annotated[float, Field(strict=True, allow_inf_nan=False, ge=0.0, le=100.0)]
Positive = Annotated[float, Field(strict=True, allow_inf_nan=False, gt=0.0, le=1000.0)]


class _Shape(BaseModel):
    model_config = {"extra": "forbid"}


class WallIO(_Shape):
    """A virtual wall: a polyline the robot must not cross."""

    kind: Literal["wall"]
    points: Annotated[list[Vertex], Field(min_length=1, max_length=MAX_VERTICES)]
    thickness: Length = 0.0


class ZoneIO(_Shape):
    """A forbidden zone: a filled polygon the robot must not enter."""

    kind: Literal["zone"]
    polygon: Annotated[list[Vertex], Field(min_length=3, max_length=MAX_VERTICES)]


class CircleIO(_Shape):
    """A round forbidden zone."""

    kind: Literal["circle"]
    x: Coordinate
    y: Coordinate
    radius: Positive


class GuidedIO(_Shape):
    """A zone crossed only along its route's lane (drawn by the dialects; kept as it is)."""

    kind: Literal["guided"]
    polygon: Annotated[list[Vertex], Field(min_length=3, max_length=MAX_VERTICES)]
    route: Annotated[list[Vertex], Field(min_length=2, max_length=MAX_VERTICES)]
    lane_width: Positive = 1.2
    start_waits: Annotated[list[Vertex], Field(max_length=MAX_VERTICES)] = []
    end_waits: Annotated[list[Vertex], Field(max_length=MAX_VERTICES)] = []


KeepoutIO = Annotated[WallIO | ZoneIO | CircleIO | GuidedIO, Field(discriminator="kind")]
KeepoutList = Annotated[list[KeepoutIO], Field(max_length=MAX_KEEPOUTS)]


def _pairs(points: list[list[float]]) -> tuple[tuple[float, float], ...]:
    return tuple((p[0], p[1]) for p in points)


def keepout_to_domain(shape: WallIO | ZoneIO | CircleIO | GuidedIO) -> Keepout:
    """The domain shape of a checked body (its own checks raise InvalidRequest: a 422)."""
    if isinstance(shape, WallIO):
        return VirtualWall(_pairs(shape.points), shape.thickness)
    if isinstance(shape, ZoneIO):
        return ForbiddenZone(_pairs(shape.polygon))
    if isinstance(shape, CircleIO):
        return CircleZone(shape.x, shape.y, shape.radius)
    return GuidedZone(_pairs(shape.polygon), _pairs(shape.route), shape.lane_width,
                      _pairs(shape.start_waits), _pairs(shape.end_waits))


def _lists(points: tuple[tuple[float, float], ...]) -> list[list[float]]:
    return [[x, y] for x, y in points]


def keepout_from_domain(keepout: Keepout) -> WallIO | ZoneIO | CircleIO | GuidedIO:
    """The body of a stored shape."""
    if isinstance(keepout, VirtualWall):
        return WallIO(kind="wall", points=_lists(keepout.points), thickness=keepout.thickness)
    if isinstance(keepout, ForbiddenZone):
        return ZoneIO(kind="zone", polygon=_lists(keepout.polygon))
    if isinstance(keepout, CircleZone):
        return CircleIO(kind="circle", x=keepout.x, y=keepout.y, radius=keepout.radius)
    return GuidedIO(kind="guided", polygon=_lists(keepout.polygon), route=_lists(keepout.route),
                    lane_width=keepout.lane_width, start_waits=_lists(keepout.start_waits),
                    end_waits=_lists(keepout.end_waits))


class SceneOut(BaseModel):
    """What moves on the map beside the robot, for drawing: all in the frame of ``map``."""

    map: str | None = Field(description="the map the robot is on (null when free)")
    stamp: float = Field(description="the runtime's clock when read [s]")
    pose: PoseOut = Field(description="the robot's pose the scan is drawn from")
    scan: list[list[float]] = Field(description="the newest lidar returns, (x, y) [m]")
    path: list[list[float]] = Field(description="the running goal's planned path, (x, y) [m]; "
                                    "empty when no goal runs")
    people: list[PoseOut] = Field(description="people near the robot on its floor (simulator)")


class PathIn(_Shape):
    """A path drawn on a map: the polyline the robot should follow, in the order drawn."""

    points: Annotated[list[Vertex], Field(min_length=2, max_length=MAX_VERTICES)]


class PathOut(BaseModel):
    """A stored path of a map (a route of the site: Galileo's clients see it too)."""

    name: str
    map: str
    points: list[list[float]] = Field(description="(x, y) [m], in the order drawn")
