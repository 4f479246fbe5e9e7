"""Small worlds written as ASCII maps, for simulator tests."""

from __future__ import annotations

from polynav.geometry import Pose2D
from polynav.maps.ascii import map_from_ascii
from polynav.site import Point, PointKind
from polynav.worlds.world import PersonRoute, World, WorldFloor


def ascii_world(
    text: str,
    *,
    resolution: float = 0.1,
    start: Pose2D,
    people: tuple[PersonRoute, ...] = (),
    points: tuple[tuple[str, Pose2D, PointKind], ...] = (),
    floors: tuple[str, ...] = ("ground",),
) -> World:
    """A world whose every floor is ``text`` (first line on top), with ``people`` on each."""
    grid = map_from_ascii(text, resolution=resolution)
    built = tuple(
        WorldFloor(
            name=name, level=n, map_name=name, map=grid,
            points=tuple(Point(p, name, pose, kind) for p, pose, kind in points),
            lift=None, people=people,
        )
        for n, name in enumerate(floors)
    )
    return World(name="test", floors=built, start_floor=floors[0], start_pose=start)
