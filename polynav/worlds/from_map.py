"""A simulation world from any floor plan: a ROS map or a MovingAI grid map.

So that anyone can try polynav on their own building (or on a benchmark's maps): the plan becomes
the simulated ground truth of one floor, with goal points and walkers placed at random (from a
seed) where the robot can really go. A MovingAI map has no scale of its own: each of its cells
becomes ``cell`` metres, drawn at ``resolution`` metres per pixel. Points lie in the largest
region the robot fits through, ``robot_radius + margin`` from any wall and at least
``point_spacing`` apart; walkers pace back and forth on straight stretches of it wide
enough for the robot to pass them.

:func:`write_world_from_map` writes the world folder (``world.yaml`` and the floor's ROS map)
atomically: it is built beside the target and renamed into place, so a bad input leaves nothing.
"""

from __future__ import annotations

import logging
import math
import os
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt
import yaml
from scipy import ndimage

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps import movingai, ros_map
from polynav.maps.map import FREE, OCCUPIED, Map, MapInfo
from polynav.robot.profile import RobotProfile
from polynav.site import Point, PointKind
from polynav.worlds.world import PersonRoute, World, WorldFloor
from polynav.worlds.world_file import WORLD_FILE

log = logging.getLogger(__name__)

_MAX_PIXELS = 40_000_000  # a 6,000 x 6,000 plan at 0.05 m is 300 m square: plenty


@dataclass(frozen=True, slots=True)
class FromMapOptions:
    """How a plan becomes a world [m].

    Attributes:
        cell: metres per MovingAI cell (ROS maps carry their own resolution).
        resolution: metres per pixel of the drawn MovingAI map.
        points: goal points to place.
        walkers: people pacing on the floor.
        seed: seeds every random choice.
        robot_radius: the robot the world is for; points keep ``robot_radius + margin`` from
            walls, and only the region such a robot can reach is used.
        margin: extra clearance of the points.
        point_spacing: points lie at least this far apart.
        walker_speed: the walkers' speed [m/s].
    """

    cell: float = 1.0
    resolution: float = 0.05
    points: int = 20
    walkers: int = 3
    seed: int = 0
    robot_radius: float = 0.25
    margin: float = 0.25
    point_spacing: float = 1.0
    walker_speed: float = 0.8

    def __post_init__(self) -> None:
        for key in ("cell", "resolution", "robot_radius", "point_spacing", "walker_speed"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value > 0.0):
                raise InvalidRequest(key, f"must be finite and > 0, got {value}")
        if not (math.isfinite(self.margin) and self.margin >= 0.0):
            raise InvalidRequest("margin", f"must be finite and >= 0, got {self.margin}")
        if self.points < 1:
            raise InvalidRequest("points", f"must be >= 1, got {self.points}")
        if self.walkers < 0:
            raise InvalidRequest("walkers", f"must be >= 0, got {self.walkers}")
        if self.cell < self.resolution:
            raise InvalidRequest("cell", "must be at least the resolution")


@dataclass(frozen=True, slots=True)
class PlannedWorld:
    """The floor plan and what was placed on it (world frame, metres)."""

    name: str
    grid: Map
    start: tuple[float, float, float]
    points: tuple[tuple[float, float, float], ...]
    walkers: tuple[tuple[tuple[float, float], tuple[float, float]], ...]


def load_plan(path: str | Path, options: FromMapOptions) -> Map:
    """The plan as an occupancy map: a ROS ``.yaml`` as it is, a MovingAI ``.map`` drawn.

    Raises:
        InvalidRequest: a missing file, an unknown extension, a plan too large to draw
            (``MapFormatError``, an ``InvalidRequest`` too, for a malformed file).
    """
    plan = Path(path)
    if not plan.is_file():
        raise InvalidRequest("map", f"{plan}: no such file")
    suffix = plan.suffix.lower()
    if suffix in (".yaml", ".yml"):
        return ros_map.load_map(plan)
    if suffix != ".map":
        raise InvalidRequest("map", f"{plan}: expected a ROS map (.yaml) or a MovingAI map (.map)")
    blocked = movingai.load_grid(plan)
    scale = max(1, int(round(options.cell / options.resolution)))
    height, width = blocked.shape[0] * scale + 2, blocked.shape[1] * scale + 2
    if height * width > _MAX_PIXELS:
        raise InvalidRequest(
            "map", f"{plan}: {blocked.shape[1]} x {blocked.shape[0]} cells at {options.cell:g} m "
            f"is {width} x {height} pixels at {options.resolution:g} m, more than {_MAX_PIXELS}"
        )
    pixels = np.ones((height, width), dtype=np.bool_)  # a wall round the edge of the plan
    pixels[1:-1, 1:-1] = np.kron(blocked[::-1], np.ones((scale, scale), dtype=np.bool_))
    data = np.where(pixels, OCCUPIED, FREE).astype(np.int8)
    resolution = options.cell / scale
    return Map(MapInfo(resolution, width, height), np.ascontiguousarray(data))


def plan_world(
    name: str, grid: Map, options: FromMapOptions, *, allow_fewer: bool = False
) -> PlannedWorld:
    """Place the start, the points and the walkers on ``grid``.

    Args:
        allow_fewer: on a plan too small for ``points`` points, place as many as fit (at
            least one) instead of refusing (benchmarks over maps of every size).

    Raises:
        InvalidRequest: no free space the robot fits in; fewer places than ``points`` (and
            ``allow_fewer`` not set, or not even one).
    """
    info = grid.info
    rng = np.random.default_rng(options.seed)
    clearance = ndimage.distance_transform_edt(grid.data == FREE) * info.resolution
    passable = clearance >= options.robot_radius + 0.5 * info.resolution
    labels, count = ndimage.label(passable, structure=np.ones((3, 3), dtype=bool))
    if count == 0:
        raise InvalidRequest("map", "no free space wide enough for the robot "
                             f"({2.0 * options.robot_radius:g} m across)")
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    region = labels == int(np.argmax(sizes))
    roomy = region & (clearance >= options.robot_radius + options.margin)
    cells = np.argwhere(roomy)
    if cells.shape[0] == 0:
        raise InvalidRequest("map", "no place leaves the robot "
                             f"{options.robot_radius + options.margin:g} m from the walls")
    wanted = options.points + 1  # the start, then the goal points
    order = rng.permutation(cells.shape[0])
    chosen: list[tuple[float, float]] = []
    spacing2 = options.point_spacing**2
    for k in order:
        iy, ix = cells[k]
        x, y = info.cell_to_world(int(ix), int(iy))
        if all((x - px) ** 2 + (y - py) ** 2 >= spacing2 for px, py in chosen):
            chosen.append((x, y))
            if len(chosen) == wanted:
                break
    if len(chosen) < wanted and not (allow_fewer and len(chosen) >= 2):
        raise InvalidRequest(
            "points", f"only {len(chosen) - 1} points fit {options.point_spacing:g} m apart "
            f"in the robot's reach; asked for {options.points}"
        )
    poses = tuple((x, y, float(rng.uniform(-math.pi, math.pi))) for x, y in chosen)
    walkers = _walker_routes(info, clearance, region, cells, rng, options)
    return PlannedWorld(name, grid, poses[0], poses[1:], walkers)


def to_world(planned: PlannedWorld, options: FromMapOptions) -> World:
    """The planned world in memory, as :func:`~polynav.worlds.load_world` would read it."""
    sx, sy, st = planned.start
    points = [Point("initial", "floor1", Pose2D(sx, sy, st), PointKind.INITIAL)]
    points += [
        Point(f"p{k:02d}", "floor1", Pose2D(x, y, theta), PointKind.GENERAL, number=k)
        for k, (x, y, theta) in enumerate(planned.points, start=1)
    ]
    people = tuple(PersonRoute((a, b), speed=options.walker_speed, loop=False)
                   for a, b in planned.walkers)
    floor = WorldFloor("floor1", 1, "floor1", planned.grid, tuple(points), None, people)
    return World(planned.name, (floor,), "floor1", Pose2D(sx, sy, st))


def _walker_routes(
    info: MapInfo,
    clearance: npt.NDArray[np.float64],
    region: npt.NDArray[np.bool_],
    cells: npt.NDArray[np.int64],
    rng: np.random.Generator,
    options: FromMapOptions,
) -> tuple[tuple[tuple[float, float], tuple[float, float]], ...]:
    """Straight stretches of at least 3 m inside the robot's region, wide enough for the robot
    to pass a walker (a walker on a 1 m wide passage would block it for as long as they pace:
    people do not pace where nobody can pass them)."""
    routes = []
    person = 0.3 + 2.0 * options.robot_radius + options.margin
    for _ in range(options.walkers):
        for _attempt in range(400):
            a, b = cells[rng.integers(cells.shape[0], size=2)]
            ax, ay = info.cell_to_world(int(a[1]), int(a[0]))
            bx, by = info.cell_to_world(int(b[1]), int(b[0]))
            length = math.hypot(bx - ax, by - ay)
            if not 3.0 <= length <= 30.0:
                continue
            steps = int(length / info.resolution) + 1
            t = np.linspace(0.0, 1.0, steps)
            line = np.column_stack((ax + t * (bx - ax), ay + t * (by - ay)))
            ix, iy = info.world_to_cells(line).T
            if np.all(region[iy, ix]) and np.all(clearance[iy, ix] >= person):
                routes.append(((ax, ay), (bx, by)))
                break
    if len(routes) < options.walkers:
        log.warning("only %d of %d walkers found a clear stretch to pace", len(routes),
                    options.walkers)
    return tuple(routes)


def write_world_from_map(
    plan: str | Path,
    out: str | Path,
    options: FromMapOptions | None = None,
    robot: RobotProfile | None = None,
) -> PlannedWorld:
    """Build a world folder at ``out`` from the plan at ``plan``; with ``robot``, the world is
    for that robot (``robot:`` in its world.yaml, written in full so the folder stands alone;
    pass its circumscribed radius as ``options.robot_radius`` so points leave it room to turn).

    Raises:
        InvalidRequest: as :func:`load_plan` and :func:`plan_world`; ``out`` exists and is not
            an empty folder, or cannot be created or written. Nothing is written then.
    """
    options = options or FromMapOptions()
    target = Path(out)
    if target.exists() and (not target.is_dir() or any(target.iterdir())):
        raise InvalidRequest("out", f"{target}: exists and is not an empty folder")
    name = Path(plan).stem or "world"
    planned = plan_world(name, load_plan(plan, options), options)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    except OSError as exc:
        # An unwritable or impossible --out is the caller's mistake, not a crash.
        raise InvalidRequest("out", f"{target}: cannot create it: {exc.strerror or exc}") from exc
    try:
        staging.chmod(0o755)  # mkdtemp's folder is private; the world is an ordinary folder
        ros_map.save_map(planned.grid, staging / "floor1.yaml")
        (staging / WORLD_FILE).write_text(_world_yaml(planned, options, robot),
                                          encoding="utf-8")
        if target.exists():
            target.rmdir()
        os.replace(staging, target)
    except OSError as exc:
        shutil.rmtree(staging, ignore_errors=True)
        raise InvalidRequest("out", f"{target}: cannot write it: {exc.strerror or exc}") from exc
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    log.info("world %r written to %s: %d points, %d walkers", name, target,
             len(planned.points), len(planned.walkers))
    return planned


def _world_yaml(
    planned: PlannedWorld, options: FromMapOptions, robot: RobotProfile | None = None
) -> str:
    sx, sy, st = planned.start
    points = [{"name": "initial", "x": sx, "y": sy, "theta": st, "kind": "initial"}]
    points += [
        {"name": f"p{k:02d}", "x": x, "y": y, "theta": theta, "kind": "general", "number": k}
        for k, (x, y, theta) in enumerate(planned.points, start=1)
    ]
    doc = {
        "name": planned.name,
        "start": {"floor": "floor1", "pose": {"x": sx, "y": sy, "theta": st}},
        "floors": [{
            "name": "floor1",
            "level": 1,
            "map": "floor1.yaml",
            "points": points,
            "people": [
                {"waypoints": [list(a), list(b)], "speed": options.walker_speed, "loop": False}
                for a, b in planned.walkers
            ],
        }],
    }
    if robot is not None:
        doc = {"name": doc["name"], "robot": robot.to_document(),
               **{k: v for k, v in doc.items() if k != "name"}}
    header = (f"# Generated by polynav world from-map (seed {options.seed}, "
              f"{options.points} points, {options.walkers} walkers).\n")
    return header + yaml.safe_dump(doc, sort_keys=False)
