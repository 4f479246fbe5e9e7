"""Generate the built-in demo world: a three-storey office/hotel/clinic building with two lifts.

Writes ``polynav/worlds/demo/`` (``floor<n>.png/.yaml`` for floors 1-3, ``world.yaml``). The
output is a pure function of this file: walls, rooms and furniture are axis-aligned rectangles
drawn into numpy grids, so running it twice gives identical bytes. Commit what it writes; the
files are package data.

Both floors share the outer walls (40 m x 24 m) and the service core with the lift car at the
same x, y. Floor 1 is an office (lobby with a front desk, a 2.0 m main corridor, a 1.8 m side
corridor, offices, a meeting room, a kitchen, an open-plan office and a print room); floor 2 is a
hotel corridor with twelve rooms, a lounge, a fitness room and service rooms; floor 3 is a clinic
(six consulting rooms, a waiting area, a nurse station). The lift doors are drawn open, so the
cars are reachable on the static maps.

Two lift cars, so that route choice, "no lift serves that floor" and an out-of-service fallback
can all happen: ``lift_1`` (car A, 2.0 m x 2.0 m) serves floors 1-3; ``lift_2`` (car B, 1.5 m x
1.8 m, carved into the service core west of car A, where floors 1 and 2 had solid core) serves
floors 1 and 2 only. Floors 1 and 2 are otherwise exactly as they were before the cars and the
third floor were added; their new points (``lift_2_outside``, ``lift_2_inside``) come last.

Before writing, the generator checks what the unit tests check again on the loaded files: every
point has 0.45 m clearance, every point is reachable from the floor's initial point by a robot
disk, and walkers keep clear of walls and of the points.

Usage: ``python tools/make_demo_world.py [--out DIR] [--preview DIR]``.
"""

from __future__ import annotations

import argparse
import logging
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import numpy.typing as npt
import yaml
from scipy import ndimage

from polynav.geometry import Pose2D
from polynav.maps.map import FREE, OCCUPIED, UNKNOWN, Map, MapInfo
from polynav.maps.ros_map import save_map
from polynav.site import Point, PointKind
from polynav.worlds.world import PersonRoute

log = logging.getLogger("make_demo_world")

REPO = Path(__file__).resolve().parent.parent
DEFAULT_OUT = REPO / "polynav" / "worlds" / "demo"

RESOLUTION = 0.05
MARGIN = 0.5  # unknown band around the building, as a surveyed ROS map has
BUILDING_W = 40.0
BUILDING_H = 24.0
OUTER = 0.2  # outer wall thickness [m]
WALL = 0.1  # interior wall thickness [m]

POINT_CLEARANCE = 0.45  # robot radius 0.25 + margin
ROBOT_RADIUS = 0.25
WALKER_POINT_DISTANCE = 0.75  # a walker passes a parked robot with a body's gap to spare

# The service core (stairs, shafts) and the lift car: identical on every floor.
CORE = (34.1, 19.0, 39.8, 23.8)
CAR = (36.0, 19.2, 38.0, 21.2)  # car floor, 2.0 m x 2.0 m
CAR_DOOR = (36.4, 19.0, 37.6, 19.2)  # 1.2 m opening in the car's south wall, drawn open
LIFT_X, LIFT_Y = 37.0, 20.2
LIFT_DOOR_HEADING = -math.pi / 2
# Car B (lift_2), floors 1-2 only: in the core west of car A, its door in the same south face.
CAR_B = (34.3, 19.2, 35.8, 21.0)
CAR_B_DOOR = (34.5, 19.0, 35.6, 19.2)
LIFT_B_X, LIFT_B_Y = 35.05, 20.1
# Where a robot waits for a car's session, off the path between that car's door and its
# outside point (so that a robot leaving the car never finds the waiting one in its way).
LIFT_1_WAIT = (38.9, 15.6)
LIFT_2_WAIT = (35.0, 14.4)

N, S, E, W = math.pi / 2, -math.pi / 2, 0.0, math.pi


@dataclass
class Floor:
    """A floor being drawn: ground truth cells, points and walker routes."""

    name: str
    level: int
    grid: npt.NDArray[np.int8] = field(init=False)
    points: list[Point] = field(default_factory=list)
    people: list[PersonRoute] = field(default_factory=list)
    access_points: list[dict[str, object]] = field(default_factory=list)

    def __post_init__(self) -> None:
        w = round((BUILDING_W + 2 * MARGIN) / RESOLUTION)
        h = round((BUILDING_H + 2 * MARGIN) / RESOLUTION)
        self.grid = np.full((h, w), UNKNOWN, dtype=np.int8)
        self._fill(0.0, 0.0, BUILDING_W, BUILDING_H, FREE)
        for rect in (
            (0.0, 0.0, BUILDING_W, OUTER),
            (0.0, BUILDING_H - OUTER, BUILDING_W, BUILDING_H),
            (0.0, 0.0, OUTER, BUILDING_H),
            (BUILDING_W - OUTER, 0.0, BUILDING_W, BUILDING_H),
        ):
            self.block(*rect)

    @property
    def info(self) -> MapInfo:
        h, w = self.grid.shape
        return MapInfo(RESOLUTION, w, h, Pose2D(-MARGIN, -MARGIN, 0.0))

    def _cells(self, x0: float, y0: float, x1: float, y1: float) -> tuple[slice, slice]:
        ix0 = round((x0 + MARGIN) / RESOLUTION)
        ix1 = round((x1 + MARGIN) / RESOLUTION)
        iy0 = round((y0 + MARGIN) / RESOLUTION)
        iy1 = round((y1 + MARGIN) / RESOLUTION)
        assert ix0 < ix1 and iy0 < iy1, (x0, y0, x1, y1)
        return slice(iy0, iy1), slice(ix0, ix1)

    def _fill(self, x0: float, y0: float, x1: float, y1: float, value: int) -> None:
        rows, cols = self._cells(x0, y0, x1, y1)
        self.grid[rows, cols] = value

    def block(self, x0: float, y0: float, x1: float, y1: float) -> None:
        """Occupy the rectangle [x0, x1] x [y0, y1] (walls, furniture)."""
        self._fill(x0, y0, x1, y1, OCCUPIED)

    def clear(self, x0: float, y0: float, x1: float, y1: float) -> None:
        """Free the rectangle (door openings, room interiors carved out of a block)."""
        self._fill(x0, y0, x1, y1, FREE)

    def hwall(self, x0: float, x1: float, y: float, doors: tuple[tuple[float, float], ...] = ()
              ) -> None:
        """A wall along x from x0 to x1 whose south face is at y, with door gaps (x from, x to)."""
        self.block(x0, y, x1, y + WALL)
        for d0, d1 in doors:
            self.clear(d0, y, d1, y + WALL)

    def vwall(self, y0: float, y1: float, x: float, doors: tuple[tuple[float, float], ...] = ()
              ) -> None:
        """A wall along y from y0 to y1 whose west face is at x, with door gaps (y from, y to)."""
        self.block(x, y0, x + WALL, y1)
        for d0, d1 in doors:
            self.clear(x, d0, x + WALL, d1)

    def point(self, name: str, x: float, y: float, theta: float,
              kind: PointKind = PointKind.GENERAL) -> None:
        # Sums of decimal coordinates carry binary noise (18.900000000000002); the file should not.
        pose = Pose2D(round(x, 6), round(y, 6), theta)
        self.points.append(Point(name, self.name, pose, kind, number=len(self.points) + 1))

    def walker(self, waypoints: list[tuple[float, float]], speed: float, *, loop: bool) -> None:
        wps = tuple((round(x, 6), round(y, 6)) for x, y in waypoints)
        self.people.append(PersonRoute(wps, speed=speed, radius=0.25, loop=loop))

    def initial(self) -> Point:
        return next(p for p in self.points if p.kind is PointKind.INITIAL)

    def service_core(self, *, car_b: bool = True) -> None:
        """The core with the lift cars, the same on every floor they serve; doors drawn open."""
        self.block(*CORE)
        self.clear(*CAR)
        self.clear(*CAR_DOOR)
        if car_b:
            self.clear(*CAR_B)
            self.clear(*CAR_B_DOOR)

    def lift_b_points(self) -> None:
        """Car B's points, appended after the floor's others (earlier numbers unchanged)."""
        self.point("lift_2_outside", LIFT_B_X, 17.6, N, PointKind.LIFT_OUTSIDE)
        self.point("lift_2_inside", LIFT_B_X, LIFT_B_Y, S, PointKind.LIFT_INSIDE)


def floor_one() -> Floor:
    """The office floor."""
    f = Floor("floor1", 1)
    f.service_core()

    # Lobby x 0.2..10.0, y 0.2..17.0, open to the main corridor (y 11.0..13.0) on its east side.
    f.vwall(0.2, 11.0, 10.0)
    f.vwall(13.0, 17.1, 10.0)
    f.block(3.0, 7.0, 7.0, 7.8)  # front desk counter
    f.block(3.0, 9.2, 7.0, 9.6)  # shelves behind the receptionist
    f.block(0.2, 1.0, 1.0, 4.0)  # sofa against the west wall
    f.block(2.0, 2.0, 2.8, 3.0)  # coffee table
    f.block(6.8, 3.3, 7.2, 3.7)  # pillar
    f.block(6.8, 14.8, 7.2, 15.2)  # pillar
    f.block(0.2, 5.5, 0.8, 6.1)  # plant
    # Restrooms north of the lobby, entered from it.
    f.hwall(0.2, 10.1, 17.0, doors=((2.0, 3.0), (7.0, 8.0)))
    f.vwall(17.1, 23.8, 5.0)
    for x in (1.4, 2.6, 3.8):
        f.block(x, 22.2, x + 0.05, 23.8)  # stall partitions
    for x in (6.4, 7.6, 8.8):
        f.block(x, 22.2, x + 0.05, 23.8)

    # Main corridor y 11.0..13.0 from the lobby (x 10.0) to the lift lobby (x 34.0).
    f.hwall(10.0, 24.1, 10.9, doors=((15.2, 16.4), (18.0, 19.2)))  # south, west of side corridor
    f.hwall(25.9, 39.8, 10.9, doors=((31.0, 32.2),))  # south, east of side corridor
    f.hwall(10.0, 34.1, 13.0, doors=((11.0, 12.2), (17.0, 18.2), (23.0, 24.2), (27.2, 28.4),
                                     (30.0, 31.2)))

    # North rooms, west to east: office 1, office 2, meeting room, kitchen; then the lift lobby.
    f.vwall(13.1, 23.8, 16.0)
    f.vwall(13.1, 23.8, 22.0)
    f.vwall(13.1, 23.8, 29.0)
    f.vwall(13.1, 19.0, 34.0)  # kitchen | lift lobby; the core closes the rest
    f.vwall(19.0, 23.8, 34.0)
    for x0, x1 in ((10.1, 16.0), (16.1, 22.0)):  # two desks against the north wall, a cabinet
        f.block(x0 + 0.8, 23.0, x0 + 2.4, 23.8)
        f.block(x0 + 3.4, 23.0, x0 + 5.0, 23.8)
        f.block(x1 - 0.5, 15.0, x1, 17.0)
    f.block(23.5, 17.5, 27.5, 18.9)  # meeting table
    f.block(22.1, 23.3, 25.0, 23.8)  # sideboard
    f.block(29.1, 22.8, 34.0, 23.8)  # kitchen counter along the outer wall
    f.block(30.8, 17.5, 32.4, 18.5)  # kitchen island
    f.block(33.2, 20.0, 34.0, 21.0)  # fridge

    # South rooms: office 3, office 4, the side corridor (x 24.1..25.9), print room, open office.
    f.vwall(0.2, 10.9, 17.0)
    f.vwall(0.2, 10.9, 24.0, doors=((2.0, 3.2),))  # office 4 | side corridor
    f.vwall(0.2, 10.9, 25.9, doors=((1.2, 2.4), (4.5, 5.7)))  # side corridor | east rooms
    for x0 in (10.1, 17.1):
        f.block(x0 + 0.8, 0.2, x0 + 2.4, 1.0)
        f.block(x0 + 3.8, 0.2, x0 + 5.4, 1.0)
    f.block(10.1, 8.0, 10.6, 10.0)  # cabinet in office 3
    f.hwall(26.0, 30.1, 3.5)  # print room x 26.0..30.0, y 0.2..3.5
    f.vwall(0.2, 3.6, 30.0)
    f.block(29.2, 1.0, 30.0, 2.6)  # printer
    for x0, y0 in ((28.0, 6.4), (33.0, 6.4), (33.0, 1.6)):  # desk clusters of the open office
        f.block(x0, y0, x0 + 3.2, y0 + 1.6)
    f.block(38.2, 5.0, 38.6, 5.4)  # pillar

    f.point("initial", 8.0, 8.5, E, PointKind.INITIAL)
    # The dock is on the lobby's west wall: the robot docks driving west.
    f.point("charger", 0.8, 14.0, W, PointKind.CHARGER)
    f.point("lobby", 5.5, 12.5, E)
    f.point("front_desk", 5.0, 6.0, N)
    f.point("office_1", 14.3, 20.5, N)
    f.point("office_2", 20.3, 20.5, N)
    f.point("meeting_room", 25.5, 15.5, N)
    f.point("kitchen", 31.6, 21.0, N)
    f.point("office_3", 14.7, 5.0, S)
    f.point("office_4", 21.7, 5.0, S)
    f.point("print_room", 28.0, 1.85, E)
    f.point("open_office", 34.6, 4.8, N)
    f.point("corridor_west", 13.5, 12.4, E)
    f.point("corridor_east", 29.0, 12.4, E)
    f.point("lift_1_outside", LIFT_X, 17.6, N, PointKind.LIFT_OUTSIDE)
    f.point("lift_1_inside", LIFT_X, LIFT_Y, S, PointKind.LIFT_INSIDE)

    # Walkers: one up and down the corridor's south lane, one crossing it between offices 2 and
    # 4, one walking the side corridor into the meeting room.
    f.walker([(11.0, 11.45), (33.0, 11.45)], 1.0, loop=False)
    f.walker([(17.6, 15.0), (17.6, 13.6), (18.6, 10.4), (18.6, 8.0)], 0.8, loop=False)
    f.walker([(25.0, 2.5), (25.0, 11.7), (23.6, 12.3), (23.6, 14.6)], 0.9, loop=False)

    # Wi-Fi: the office network on both bands by the lobby, a guest network by the kitchen.
    f.access_points += [
        {"ssid": "polynav-office", "x": 9.0, "y": 12.0, "frequency": 2437,
         "security": "WPA2", "password": "office-2437"},
        {"ssid": "polynav-office-5G", "x": 9.0, "y": 12.0, "frequency": 5260,
         "security": "WPA WPA2", "password": "office-5260"},
        {"ssid": "polynav-guest", "x": 31.0, "y": 18.0, "frequency": 2462,
         "security": "", "password": ""},
    ]
    f.lift_b_points()
    return f


def floor_two() -> Floor:
    """The hotel floor: rooms off one corridor, the same outer walls and lift."""
    f = Floor("floor2", 2)
    f.service_core()

    # Lounge x 0.2..8.0, y 6.0..18.0, open to the corridor; housekeeping south, fitness north.
    f.hwall(0.2, 8.1, 5.9, doors=((5.5, 6.7),))
    f.hwall(0.2, 8.1, 18.0, doors=((5.5, 6.7),))
    f.vwall(0.2, 11.0, 8.0)
    f.vwall(13.0, 23.8, 8.0)
    f.block(0.2, 8.0, 1.0, 16.0)  # sofas along the west wall
    f.block(3.2, 13.2, 4.8, 14.2)  # lounge table
    f.block(0.2, 0.2, 2.2, 2.2)  # housekeeping: linen shelves
    f.block(6.0, 0.2, 8.0, 1.0)  # laundry carts parked along the wall
    f.block(1.5, 22.6, 3.5, 23.8)  # fitness: treadmills
    f.block(4.0, 22.6, 6.0, 23.8)

    # Corridor y 11.0..13.0 from the lounge to the lift lobby; twelve rooms off it.
    bounds = (8.0, 12.4, 16.7, 21.0, 25.3, 29.6, 34.0)
    north_doors = tuple((a + 0.2, a + 1.3) for a in (b + 0.1 for b in bounds[:-1]))
    f.hwall(8.0, 34.1, 13.0, doors=north_doors)
    f.hwall(8.0, 39.8, 10.9, doors=(*north_doors, (36.0, 37.2)))
    for b in bounds[1:-1]:
        f.vwall(13.1, 23.8, b)
        f.vwall(0.2, 10.9, b)
    f.vwall(13.1, 19.0, 34.0)
    f.vwall(0.2, 10.9, 34.0)
    rooms: list[tuple[str, float, float, float]] = []
    for n, b in enumerate(bounds[:-1]):
        a, e = b + 0.1, bounds[n + 1]  # room interior x a..e
        # North room: bathroom beside the entry hall, bed on the far wall, desk on the side.
        f.hwall(a + 1.5, e, 15.6, doors=((a + 1.8, a + 2.6),))
        f.vwall(13.1, 15.7, a + 1.5)
        f.block(a + 1.3, 21.6, a + 2.9, 23.8)
        f.block(e - 0.5, 17.0, e, 18.2)
        rooms.append((f"room_{201 + 2 * n}", a + 2.1, 19.0, N))
        # South room: the mirror image.
        f.hwall(a + 1.5, e, 8.3, doors=((a + 1.8, a + 2.6),))
        f.vwall(8.3, 10.9, a + 1.5)
        f.block(a + 1.3, 0.2, a + 2.9, 2.4)
        f.block(e - 0.5, 5.8, e, 7.0)
        rooms.append((f"room_{202 + 2 * n}", a + 2.1, 5.0, S))
    # Staff room south of the lift lobby.
    f.block(38.0, 0.2, 39.8, 3.0)  # lockers
    f.block(35.0, 4.0, 36.6, 5.2)  # table

    f.point("initial", 36.0, 15.0, W, PointKind.INITIAL)
    f.point("lounge", 4.0, 11.0, N)
    f.point("fitness_room", 4.0, 20.5, N)
    f.point("housekeeping", 4.0, 3.5, S)
    f.point("staff_room", 36.6, 7.5, S)
    f.point("corridor_west", 10.0, 12.4, E)
    f.point("corridor_east", 31.5, 12.4, E)
    f.point("lift_1_outside", LIFT_X, 17.6, N, PointKind.LIFT_OUTSIDE)
    f.point("lift_1_inside", LIFT_X, LIFT_Y, S, PointKind.LIFT_INSIDE)
    for room in sorted(rooms):
        f.point(*room)

    f.walker([(9.0, 11.45), (33.0, 11.45)], 1.0, loop=False)
    a = bounds[2] + 0.1
    f.walker([(a + 0.75, 14.5), (a + 0.75, 9.5)], 0.7, loop=False)  # room 205 to room 206
    f.walker([(2.0, 9.0), (6.5, 9.0), (6.5, 15.0), (2.0, 15.0)], 0.8, loop=True)  # the lounge

    # Wi-Fi: the hotel's own network in the corridor.
    f.access_points.append(
        {"ssid": "polynav-hotel", "x": 20.0, "y": 12.0, "frequency": 2412,
         "security": "WPA2", "password": "hotel-2412"}
    )
    f.lift_b_points()
    return f


def floor_three() -> Floor:
    """The clinic floor: consulting rooms off one corridor; car A stops here, car B does not."""
    f = Floor("floor3", 3)
    f.service_core(car_b=False)

    # Waiting area x 0.2..8.0, y 0.2..23.8 open to the corridor (y 11.0..13.0) at x 8.0.
    f.vwall(0.2, 11.0, 8.0)
    f.vwall(13.0, 23.8, 8.0)
    f.block(0.2, 4.0, 0.8, 20.0)  # benches along the west wall
    f.block(3.0, 16.0, 5.0, 17.0)  # magazine table
    f.block(3.0, 6.0, 5.0, 7.0)  # children's corner table
    f.hwall(8.0, 34.1, 13.0, doors=((9.5, 10.7), (16.5, 17.7), (23.5, 24.7), (29.0, 30.2)))
    f.hwall(8.0, 39.8, 10.9, doors=((9.5, 10.7), (16.5, 17.7), (23.5, 24.7), (29.0, 30.2),
                                    (36.0, 37.2)))
    for x in (15.0, 22.0, 28.0):
        f.vwall(13.1, 23.8, x)
        f.vwall(0.2, 10.9, x)
    f.vwall(13.1, 19.0, 34.0)
    f.vwall(0.2, 10.9, 34.0)
    for x1 in (15.0, 22.0, 28.0, 34.0):
        f.block(x1 - 2.0, 22.6, x1, 23.8)  # examination couch, north rooms
        f.block(x1 - 1.6, 0.2, x1, 1.6)  # desk, south rooms
    f.block(36.0, 4.0, 38.0, 6.0)  # nurse station counter, east of the last south room
    f.block(34.1, 0.2, 35.0, 3.0)  # medicine cabinets

    f.point("initial", 36.0, 15.0, W, PointKind.INITIAL)
    f.point("waiting_area", 4.0, 12.0, E)
    f.point("corridor_west", 11.5, 12.45, E)
    f.point("corridor_east", 31.5, 12.45, E)
    f.point("nurse_station", 37.0, 8.0, S)
    f.point("lift_1_outside", LIFT_X, 17.6, N, PointKind.LIFT_OUTSIDE)
    f.point("lift_1_inside", LIFT_X, LIFT_Y, S, PointKind.LIFT_INSIDE)
    f.point("room_301", 11.5, 18.0, N)
    f.point("room_302", 11.5, 6.0, S)
    f.point("room_303", 18.5, 18.0, N)
    f.point("room_304", 18.5, 6.0, S)
    f.point("room_305", 25.0, 18.0, N)
    f.point("room_306", 25.0, 6.0, S)
    f.point("room_307", 31.0, 18.0, N)
    f.point("room_308", 31.0, 6.0, S)

    f.walker([(10.0, 11.45), (32.0, 11.45)], 0.9, loop=False)
    return f


def floor_map(f: Floor) -> Map:
    return Map(f.info, f.grid.copy())


def check(f: Floor) -> list[str]:
    """What is wrong with a floor; empty when it meets the demo's promises."""
    problems: list[str] = []
    grid = floor_map(f)
    occupied = grid.data >= OCCUPIED
    # Distance [m] from each cell centre to the nearest occupied cell's edge.
    clearance = ndimage.distance_transform_edt(~occupied) * RESOLUTION - RESOLUTION / 2

    def cell(x: float, y: float) -> tuple[int, int]:
        return grid.info.world_to_cell(x, y)

    for p in f.points:
        ix, iy = cell(p.pose.x, p.pose.y)
        if grid.data[iy, ix] != FREE or clearance[iy, ix] < POINT_CLEARANCE:
            problems.append(f"{f.name}: point {p.name} clearance {clearance[iy, ix]:.2f} m")
    start = f.initial().pose
    for radius in (ROBOT_RADIUS, POINT_CLEARANCE - 0.01):
        passable = (grid.data == FREE) & (clearance >= radius)
        labels, _ = ndimage.label(passable)
        ix, iy = cell(start.x, start.y)
        home = labels[iy, ix]
        for p in f.points:
            ix, iy = cell(p.pose.x, p.pose.y)
            if labels[iy, ix] != home:
                problems.append(f"{f.name}: {p.name} unreachable for a {radius} m disk")
    for n, person in enumerate(f.people):
        wps = np.asarray(person.waypoints, dtype=float)
        if person.loop:
            wps = np.vstack([wps, wps[:1]])
        for a, b in zip(wps[:-1], wps[1:], strict=True):
            steps = max(2, int(np.hypot(*(b - a)) / 0.02))
            for t in np.linspace(0.0, 1.0, steps):
                x, y = a + t * (b - a)
                ix, iy = cell(x, y)
                if clearance[iy, ix] < person.radius + 0.05:
                    problems.append(f"{f.name}: walker {n} scrapes a wall at ({x:.2f}, {y:.2f})")
                    break
                for p in f.points:
                    d = math.hypot(x - p.pose.x, y - p.pose.y)
                    if d < WALKER_POINT_DISTANCE:
                        problems.append(f"{f.name}: walker {n} passes {d:.2f} m from {p.name}")
                        break
    return problems


def lift_cars(floors: list[Floor]) -> list[dict[str, object]]:
    """The ``lifts:`` entries: each car's shaft, the floors it serves, its points and timing."""
    def shaft(car: tuple[float, float, float, float], door: tuple[float, float, float, float],
              x: float, y: float) -> dict[str, object]:
        return {"x": x, "y": y, "width": round(car[2] - car[0], 6),
                "depth": round(car[3] - car[1], 6), "door_heading": LIFT_DOOR_HEADING,
                "door_width": round(door[2] - door[0], 6)}

    names = [f.name for f in floors]
    return [
        {"name": "lift_1", **shaft(CAR, CAR_DOOR, LIFT_X, LIFT_Y), "floors": names,
         "outside": "lift_1_outside", "inside": "lift_1_inside",
         "waiting": {"x": LIFT_1_WAIT[0], "y": LIFT_1_WAIT[1]},
         "speed": 1.0, "floor_height": 3.5, "door_time": 2.5, "capacity": 2},
        {"name": "lift_2", **shaft(CAR_B, CAR_B_DOOR, LIFT_B_X, LIFT_B_Y), "floors": names[:2],
         "outside": "lift_2_outside", "inside": "lift_2_inside",
         "waiting": {"x": LIFT_2_WAIT[0], "y": LIFT_2_WAIT[1]},
         "speed": 0.8, "floor_height": 3.5, "door_time": 2.5, "capacity": 1},
    ]


def check_waiting(floors: list[Floor]) -> list[str]:
    """Waiting spots: free, clear by a point's margin, and reachable on the floors they serve."""
    problems: list[str] = []
    for car in lift_cars(floors):
        wait = car["waiting"]
        assert isinstance(wait, dict)
        served = car["floors"]
        assert isinstance(served, list)
        for f in floors:
            if f.name not in served:
                continue
            probe = Floor.__new__(Floor)
            probe.name, probe.level, probe.grid = f.name, f.level, f.grid
            probe.points = [*f.points, Point("wait", f.name, Pose2D(wait["x"], wait["y"], 0.0))]
            probe.people, probe.access_points = f.people, f.access_points
            problems += [p for p in check(probe) if "wait" in p]
    return problems


def world_document(floors: list[Floor]) -> dict[str, object]:
    """The ``world.yaml`` content (see :mod:`polynav.worlds.world_file`)."""
    start = floors[0].initial().pose
    lift = {
        "x": LIFT_X, "y": LIFT_Y, "width": CAR[2] - CAR[0], "depth": CAR[3] - CAR[1],
        "door_heading": LIFT_DOOR_HEADING, "door_width": CAR_DOOR[2] - CAR_DOOR[0],
    }
    # Differences of decimal coordinates carry binary noise (2.0000000000000018).
    lift = {k: v if k == "door_heading" else round(v, 6) for k, v in lift.items()}
    docs = []
    for f in floors:
        points = [
            {"name": p.name, "x": p.pose.x, "y": p.pose.y, "theta": p.pose.theta,
             "kind": p.kind.value, "number": p.number}
            for p in f.points
        ]
        people = [
            {"waypoints": [list(wp) for wp in r.waypoints], "speed": r.speed,
             "radius": r.radius, "loop": r.loop}
            for r in f.people
        ]
        docs.append({
            "name": f.name, "level": f.level, "map": f"{f.name}.yaml", "map_name": f.name,
            "lift": dict(lift), "points": points, "people": people,
            "access_points": f.access_points,
        })
    return {
        "name": "demo",
        "start": {"floor": floors[0].name,
                  "pose": {"x": start.x, "y": start.y, "theta": start.theta}},
        "floors": docs,
        "lifts": lift_cars(floors),
        "doors": DOORS,
        "carts": CARTS,
    }


# Electronic doors and gates: two fire doors across floor 2's corridor (between the rooms'
# doors), and a security gate across the mouth of floor 1's lobby onto the main corridor.
DOORS: list[dict[str, object]] = [
    {"name": "fire_door_west", "floor": "floor2", "x1": 15.3, "y1": 10.9, "x2": 15.3,
     "y2": 13.0, "kind": "door", "open_time": 2.0, "close_time": 2.0},
    {"name": "fire_door_east", "floor": "floor2", "x1": 28.2, "y1": 10.9, "x2": 28.2,
     "y2": 13.0, "kind": "door", "open_time": 2.0, "close_time": 2.0},
    {"name": "lobby_gate", "floor": "floor1", "x1": 10.05, "y1": 11.0, "x2": 10.05,
     "y2": 13.0, "kind": "gate", "open_time": 1.5, "close_time": 1.5},
]

# Carts and a cabin (polynav.worlds.carts): two carts parked in the lobby's south-east corner,
# away from the routes (the robot docks driving east, from the lobby), and a cabin at its
# parking spot in floor 2's housekeeping room (docked driving west).
CARTS: list[dict[str, object]] = [
    {"name": "cart_1", "kind": "cart", "floor": "floor1", "x": 8.6, "y": 2.0, "theta": 0.0,
     "length": 0.9, "width": 0.7, "mass": 40.0},
    {"name": "cart_2", "kind": "cart", "floor": "floor1", "x": 8.6, "y": 4.6, "theta": 0.0,
     "length": 0.9, "width": 0.7, "mass": 55.0},
    {"name": "cabin_1", "kind": "cabin", "floor": "floor2", "x": 1.6, "y": 4.3,
     "theta": 3.141592653589793, "length": 0.9, "width": 0.7, "mass": 35.0,
     "cabin_id": "CAB-0001"},
]


HEADER = """\
# The built-in demo world: a three-storey building with two lifts (lift_1: floors 1-3,
# lift_2: floors 1-2).
# Generated by tools/make_demo_world.py; edit that script and re-run it, not this file.
# Lengths in metres, angles in radians; the charger heading is the docking direction.
"""


def write(floors: list[Floor], out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    for f in floors:
        save_map(floor_map(f), out / f"{f.name}.yaml", image_format="png", mode="trinary")
    text = yaml.safe_dump(world_document(floors), sort_keys=False, default_flow_style=None,
                          width=100)
    (out / "world.yaml").write_text(HEADER + text, encoding="utf-8")


def preview(f: Floor, path: Path, scale: int = 2) -> None:
    """A picture of the floor with its points (blue, heading ticks) and walker routes (red)."""
    from PIL import Image, ImageDraw

    grid = f.grid[::-1]
    rgb = np.full(grid.shape + (3,), 255, dtype=np.uint8)
    rgb[grid == OCCUPIED] = (30, 30, 30)
    rgb[grid == UNKNOWN] = (180, 180, 180)
    img = Image.fromarray(rgb).resize((grid.shape[1] * scale, grid.shape[0] * scale),
                                      Image.NEAREST)
    draw = ImageDraw.Draw(img)
    height = grid.shape[0]

    def px(x: float, y: float) -> tuple[float, float]:
        return ((x + MARGIN) / RESOLUTION * scale, (height - (y + MARGIN) / RESOLUTION) * scale)

    for person in f.people:
        wps = [px(x, y) for x, y in person.waypoints]
        if person.loop:
            wps.append(wps[0])
        draw.line(wps, fill=(220, 40, 40), width=2)
    colours = {PointKind.CHARGER: (0, 160, 0), PointKind.INITIAL: (200, 120, 0)}
    for p in f.points:
        x, y, th = p.pose.x, p.pose.y, p.pose.theta
        cx, cy = px(x, y)
        r = POINT_CLEARANCE / RESOLUTION * scale
        colour = colours.get(p.kind, (30, 80, 220))
        draw.ellipse((cx - r, cy - r, cx + r, cy + r), outline=colour, width=2)
        draw.line((cx, cy, *px(x + 0.7 * math.cos(th), y + 0.7 * math.sin(th))), fill=colour,
                  width=3)
        draw.text((cx + r + 2, cy - 6), p.name, fill=colour)
    img.save(path)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT)
    parser.add_argument("--preview", type=Path, help="also draw <floor>.preview.png here")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    floors = [floor_one(), floor_two(), floor_three()]
    problems = [p for f in floors for p in check(f)] + check_waiting(floors)
    if problems:
        for p in problems:
            log.error("%s", p)
        return 1
    write(floors, args.out)
    log.info("wrote %s", args.out)
    if args.preview:
        args.preview.mkdir(parents=True, exist_ok=True)
        for f in floors:
            preview(f, args.preview / f"{f.name}.preview.png")
        log.info("previews in %s", args.preview)
    return 0


if __name__ == "__main__":
    sys.exit(main())
