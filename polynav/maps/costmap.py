"""The layered costmap: what the planner and the controller read (Lu et al., IROS 2014).

Five layers, each keeping its own state, compose the master grid in this order:

1. :class:`~polynav.maps.layers.static.StaticLayer`: the map (overwrites);
2. :class:`~polynav.maps.layers.keepout.KeepoutLayer`: virtual walls and forbidden zones (LETHAL);
3. :class:`~polynav.maps.layers.obstacle.ObstacleLayer`: the live lidar (marks and clears);
4. the leaves of shut doors the robot is not opening (LETHAL, :meth:`Costmap.set_shut_doors`);
5. :class:`~polynav.maps.layers.inflation.InflationLayer`: robot radius and decaying costs.

An update first asks every layer which cells it changed (``update_bounds``; inflation grows that
window by its radius), then resets and recomposes the master *inside that window only*
(``update_costs``), as Nav2's ``LayeredCostmap::updateMap``. A scan on one side of a large map
therefore leaves the far side alone, and a robot standing still in a static scene redraws almost
nothing. Inflation, the costly step, then runs only round the cells whose composed cost (every
layer below it) really changed within that window. Extra layers (a later speed or semantic
layer) slot in between obstacle and the shut doors.

The master is the body's view: what the controller, the recoveries and a step aside must not
touch. The global planner plans on :meth:`Costmap.planning_costs`, the master without the shut
doors' leaves: a route may cross a door the robot will open on its way.

Outside the map, :meth:`Costmap.cost_at` answers LETHAL: the robot knows nothing there, there is
no grid to plan on, and a controller must treat leaving the map like hitting a wall.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.errors import ConfigError, InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.interface import CostGrid, CostmapLayer, Window
from polynav.maps.keepout import Keepout, VirtualWall
from polynav.maps.layers import inflation as inflation_kernel
from polynav.maps.layers import obstacle as obstacle_kernel
from polynav.maps.layers import window as win
from polynav.maps.layers.inflation import InflationLayer
from polynav.maps.layers.keepout import KeepoutLayer
from polynav.maps.layers.obstacle import ObstacleLayer
from polynav.maps.layers.static import StaticLayer
from polynav.maps.map import Map, MapInfo
from polynav.robot.interface import LaserScan

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class CostmapConfig:
    """How the costmap turns a map, keepouts and scans into costs (SI units).

    Attributes:
        robot_radius: inscribed radius [m]; cells this close to an obstacle are INSCRIBED.
        inflation_radius: how far [m] obstacles raise costs; at least ``robot_radius``.
        cost_scaling_factor: decay rate [1/m] of the cost between the two radii.
        lethal_threshold: map occupancy (0..100) at or above which a cell is LETHAL.
        track_unknown: unknown map cells are UNKNOWN if True, else FREE.
        obstacle_max_range: scan returns nearer than this [m] mark obstacles.
        raytrace_max_range: beams clear free space up to this distance [m].
        obstacle_layer: use the live scan at all.
        range_noise: standard deviation [m] of the lidar's range noise; a return does not clear
            the cells within 3 of it in front of itself (:mod:`polynav.maps.layers.obstacle`).
        inscribed_cell_margin: cells added to ``robot_radius`` for INSCRIBED (0..1).
            Distances run between cell centres, but the footprint check takes a LETHAL cell as
            the full square it covers: a disk whose centre is half a cell beyond its radius
            from a cell's centre touches the cell's side. A planner with no body check of its
            own (a disk's) needs the half cell to plan no way the controller then stops at.
    """

    robot_radius: float = 0.25
    inflation_radius: float = 0.55
    cost_scaling_factor: float = 3.0
    lethal_threshold: int = 65
    track_unknown: bool = False
    obstacle_max_range: float = 6.0
    raytrace_max_range: float = 8.0
    obstacle_layer: bool = True
    range_noise: float = 0.01
    inscribed_cell_margin: float = 0.0

    def __post_init__(self) -> None:
        _check(self.robot_radius >= 0.0, "robot_radius", "must be >= 0")
        _check(
            self.inflation_radius >= self.robot_radius,
            "inflation_radius",
            f"must be >= robot_radius ({self.robot_radius})",
        )
        _check(self.cost_scaling_factor >= 0.0, "cost_scaling_factor", "must be >= 0")
        _check(1 <= self.lethal_threshold <= 100, "lethal_threshold", "must be within 1..100")
        _check(self.obstacle_max_range > 0.0, "obstacle_max_range", "must be > 0")
        _check(self.raytrace_max_range > 0.0, "raytrace_max_range", "must be > 0")
        _check(self.range_noise >= 0.0, "range_noise", "must be >= 0")
        _check(0.0 <= self.inscribed_cell_margin <= 1.0, "inscribed_cell_margin",
               "must be within 0..1")
        for name in (
            "robot_radius",
            "inflation_radius",
            "cost_scaling_factor",
            "obstacle_max_range",
            "raytrace_max_range",
            "range_noise",
        ):
            _check(math.isfinite(getattr(self, name)), name, "must be finite")


def _check(ok: bool, field: str, reason: str) -> None:
    if not ok:
        raise ConfigError(f"costmap.{field}", reason)


def _cost_at(info: MapInfo, grid: npt.NDArray[np.uint8], x: float, y: float) -> int:
    ix, iy = info.world_to_cell(x, y)
    if not info.contains(ix, iy):
        return costs.LETHAL
    return int(grid[iy, ix])


@dataclass(frozen=True, slots=True, eq=False)
class CostSnapshot:
    """A frozen copy of the master costs, safe to hand to a planner on another thread.

    ``costs`` is a read-only copy: later costmap updates do not change it.
    """

    info: MapInfo
    costs: npt.NDArray[np.uint8]

    def cost_at(self, x: float, y: float) -> int:
        """Cost of the cell holding world point (x, y) [m]; LETHAL outside the map."""
        return _cost_at(self.info, self.costs, x, y)


class Costmap:
    """Master costs composed from static, keepout, obstacle and inflation layers.

    Args:
        grid: the occupancy map.
        config: costmap parameters.
        extra_layers: more layers, composed after the obstacle layer and before inflation. They
            must work on ``grid.info``'s geometry.
    """

    def __init__(
        self,
        grid: Map,
        config: CostmapConfig,
        *,
        extra_layers: Sequence[CostmapLayer] = (),
    ) -> None:
        self._config = config
        self._extra = tuple(extra_layers)
        self._pose = Pose2D()
        self._last_window: Window | None = None
        self._build(grid, keepouts=(), shut=())

    @classmethod
    def from_map(cls, grid: Map, config: CostmapConfig) -> Costmap:
        """The standard costmap over ``grid`` (the layers of the module docstring)."""
        return cls(grid, config)

    def _build(self, grid: Map, *, keepouts: Sequence[Keepout],
               shut: Sequence[VirtualWall]) -> None:
        cfg = self._config
        info = grid.info
        self._info = info
        self._static = StaticLayer(
            grid, lethal_threshold=cfg.lethal_threshold, track_unknown=cfg.track_unknown
        )
        self._keepout = KeepoutLayer(info, keepouts)
        self._obstacle: ObstacleLayer | None = None
        if cfg.obstacle_layer:
            self._obstacle = ObstacleLayer(
                info,
                obstacle_max_range=cfg.obstacle_max_range,
                raytrace_max_range=cfg.raytrace_max_range,
                range_noise=cfg.range_noise,
            )
        self._inflation = InflationLayer(
            info,
            robot_radius=cfg.robot_radius + cfg.inscribed_cell_margin * info.resolution,
            inflation_radius=cfg.inflation_radius,
            cost_scaling_factor=cfg.cost_scaling_factor,
        )
        layers: list[CostmapLayer] = [self._static, self._keepout]
        if self._obstacle is not None:
            layers.append(self._obstacle)
        layers.extend(self._extra)
        self._shut = KeepoutLayer(info, shut)
        self._shut_groups = self._groups_of_shut()
        layers.append(self._shut)
        layers.append(self._inflation)
        self._layers = tuple(layers)
        self._default = costs.UNKNOWN if cfg.track_unknown else costs.FREE
        self._master = np.full((info.height, info.width), self._default, dtype=np.uint8)
        # The layers below inflation, composed: what inflation grows. Kept apart from the master
        # so that an update can tell which cells really changed (see :meth:`update`).
        self._base = self._master.copy()
        self._view = self._master.view()
        self._view.flags.writeable = False
        self.update()

    @property
    def config(self) -> CostmapConfig:
        return self._config

    @property
    def info(self) -> MapInfo:
        return self._info

    @property
    def costs(self) -> npt.NDArray[np.uint8]:
        """The master costs ``[iy, ix]``, live and read-only; take a :meth:`snapshot` to keep."""
        return self._view

    @property
    def layers(self) -> tuple[CostmapLayer, ...]:
        """The layers in composition order."""
        return self._layers

    @property
    def keepouts(self) -> tuple[Keepout, ...]:
        return self._keepout.keepouts

    @property
    def shut_doors(self) -> tuple[VirtualWall, ...]:
        """The leaves drawn LETHAL for the body (:meth:`set_shut_doors`)."""
        return self._shut.keepouts  # type: ignore[return-value]

    @property
    def last_window(self) -> Window | None:
        """The window the last update recomposed (``None``: nothing changed); for diagnostics."""
        return self._last_window

    def snapshot(self) -> CostSnapshot:
        """A frozen copy of the current costs."""
        frozen = self._master.copy()
        frozen.flags.writeable = False
        return CostSnapshot(self._info, frozen)

    def cost_at(self, x: float, y: float) -> int:
        """Cost of the cell holding world point (x, y) [m]; LETHAL outside the map (see module)."""
        return _cost_at(self._info, self._master, x, y)

    def map_cost_at(self, x: float, y: float) -> int:
        """The cost of (x, y) from the map and keepouts alone, inflated, without what the lidar
        marked: whether a cell the planner finds occupied is held by the building (for good) or
        by something standing there now, which may leave. Composes a small window on demand,
        so it is for the odd question, not for every cell of a search."""
        ix, iy = self._info.world_to_cell(x, y)
        if not self._info.contains(ix, iy):
            return costs.LETHAL
        width, height = self._info.width, self._info.height
        reach = self._inflation.cell_radius
        cell = (ix, iy, ix + 1, iy + 1)
        read = win.grow(cell, reach, width, height)
        # Full size, since the layers index by window, but only ``read`` is touched (an empty
        # array's pages are not: a 200 m floor's 16 MB costs nothing).
        scratch = np.empty((height, width), dtype=np.uint8)
        self._compose_map_only(scratch, read, cell)
        return int(scratch[iy, ix])

    def map_costs(self) -> CostSnapshot:
        """The costs of the whole grid from the map and keepouts alone, inflated: what the
        planner would see with nothing standing about. Whether a way the planner finds closed
        is closed by the building (for good) or by something that may move on (another robot
        at a corridor's mouth, a trolley). Composed afresh on each call: for the odd question."""
        info = self._info
        whole = win.full(info.width, info.height)
        grid = np.empty((info.height, info.width), dtype=np.uint8)
        self._compose_map_only(grid, whole, whole)
        grid.flags.writeable = False
        return CostSnapshot(info, grid)

    def _compose_map_only(self, grid: npt.NDArray[np.uint8], read: Window,
                          inflate: Window) -> None:
        """The costs without the lidar's marks, for :meth:`map_cost_at` and :meth:`map_costs`
        (:meth:`_compose`)."""
        self._compose(grid, (self._static, self._keepout), read, inflate)

    def _compose(self, grid: npt.NDArray[np.uint8], layers: Sequence[CostmapLayer],
                 read: Window, inflate: Window) -> None:
        """Write ``layers`` over ``read`` and inflate them over ``inflate`` (within it)."""
        grid[win.slices(read)] = self._default
        for layer in layers:
            layer.update_costs(grid, read)
        self._inflation.update_costs(grid, inflate)

    def update_scan(self, pose: Pose2D, scan: LaserScan) -> None:
        """Mark and clear ``scan`` taken at robot ``pose``, then recompose the changed window.

        Does nothing but record the pose when the obstacle layer is off.
        """
        self._pose = pose
        if self._obstacle is not None:
            self._obstacle.add_scan(pose, scan)
        self.update()

    def clear_obstacles(self) -> None:
        """Forget everything the lidar marked (the "clear costmap" recovery)."""
        if self._obstacle is not None:
            self._obstacle.clear()
        log.info("costmap: obstacles cleared")
        self.update()

    def clear_obstacles_around(self, x: float, y: float, radius: float) -> None:
        """Forget the lidar's marks within ``radius`` [m] of (x, y) (a recovery's first rung)."""
        if self._obstacle is not None and self._obstacle.clear_around(x, y, radius) is not None:
            log.info("costmap: obstacles cleared within %.2f m of (%.2f, %.2f)", radius, x, y)
            self.update()

    def set_passable(self, passable: npt.NDArray[np.bool_] | None) -> None:
        """Cells ``[iy, ix]`` the lidar's obstacles never take (doors the robot opens on its
        way, :meth:`~polynav.maps.layers.obstacle.ObstacleLayer.set_passable`); ``None``:
        none. The map and keepouts still count there."""
        if self._obstacle is not None and self._obstacle.set_passable(passable) is not None:
            self.update()

    def set_shut_doors(self, leaves: Sequence[VirtualWall]) -> None:
        """The leaves of the doors that stand shut and that the robot is not opening: LETHAL
        to the body (the controller, a recovery's back-up, a step aside from a walker), which
        otherwise took a doorway for free floor, door leaves being passable to the lidar's
        marks (:meth:`set_passable`), and backed into a leaf it had just passed (bench fleet,
        floor 2's fire doors). The global planner does not see them
        (:meth:`planning_costs`)."""
        leaves = tuple(leaves)
        if leaves == self._shut.keepouts:
            return
        self._shut.set_keepouts(leaves)
        self._shut_groups = self._groups_of_shut()
        self.update()

    def planning_costs(self) -> CostGrid:
        """What the global planner plans on: the master, or, while doors stand shut
        (:meth:`set_shut_doors`), a copy recomposed round their leaves without them (with
        every other layer and inflation), so a route may cross a door the robot will open."""
        if not self._shut_groups:
            return self
        info = self._info
        width, height = info.width, info.height
        reach = self._inflation.cell_radius
        grid = self._master.copy()
        # Full size, since the layers index by window, but only the windows are touched.
        scratch = np.empty((height, width), dtype=np.uint8)
        below = [layer for layer in self._layers[:-1] if layer is not self._shut]
        for group in self._shut_groups:
            inflate = win.grow(group, reach, width, height)
            self._compose(scratch, below, win.grow(inflate, reach, width, height), inflate)
            grid[win.slices(inflate)] = scratch[win.slices(inflate)]
        grid.flags.writeable = False
        return CostSnapshot(info, grid)

    def _groups_of_shut(self) -> list[Window]:
        if not self._shut.keepouts:
            return []
        return win.groups_of_mask(self._shut.mask, 2 * self._inflation.cell_radius + 1)

    def set_keepouts(self, keepouts: Sequence[Keepout]) -> None:
        """Replace every keepout; only the cells that changed (plus inflation) are redrawn."""
        self._keepout.set_keepouts(keepouts)
        log.info("costmap: %d keepouts set", len(keepouts))
        self.update()

    def set_static_map(self, grid: Map) -> None:
        """Swap the map (a floor change, or the same floor re-mapped).

        The lidar's obstacles are forgotten: they were seen in the old map's frame, and the next
        scans see them again. Keepouts are kept and drawn on the new grid, since they are world
        shapes the caller owns: call :meth:`set_keepouts` when they belong to the old map only.
        With the same geometry (size, resolution, origin) only the cells that differ are
        redrawn; with another, every layer starts afresh on the new grid.

        Raises:
            InvalidRequest: the geometry changes and extra layers were given, which only their
                owner can rebuild: make a new :class:`Costmap`.
        """
        if grid.info == self._info:
            self._static.set_map(grid)
            if self._obstacle is not None:
                self._obstacle.clear()
            self.update()
            return
        if self._extra:
            raise InvalidRequest(
                "map", "a costmap with extra layers cannot change geometry; build a new Costmap"
            )
        log.info(
            "costmap: new map %dx%d at %g m",
            grid.info.width,
            grid.info.height,
            grid.info.resolution,
        )
        self._build(grid, keepouts=self._keepout.keepouts,
                    shut=self.shut_doors)

    def update(self) -> Window | None:
        """Recompose the master wherever a layer changed; returns that window (or ``None``).

        :meth:`update_scan`, :meth:`set_keepouts` and the other mutators call it; call it
        yourself after changing an extra layer.
        """
        window: Window | None = None
        for layer in self._layers:
            window = layer.update_bounds(self._pose, window)
        window = win.clip(window, self._info.width, self._info.height)
        self._last_window = window
        if window is None:
            return None
        region = win.slices(window)
        before = self._base[region].copy()
        self._base[region] = self._default
        for layer in self._layers[:-1]:
            layer.update_costs(self._base, window)
        changed = before != self._base[region]
        reach = self._inflation.cell_radius
        # Inflation only where it can differ: within its radius of a cell whose composed cost
        # changed, group by group. A scan's window spans every cell its beams flipped in the
        # obstacle layer (wall cells marked again from a new angle, free space seen again),
        # most of which change nothing below inflation, and the real changes (a walker here,
        # a robot there) are often far apart: growing each group of them on its own keeps the
        # distance transform, the costliest step of an update, to a few small windows.
        # Every group's window is reset to the composed costs before any is inflated, so no
        # inflation reads a lethal cell another group has just cleared; a window that overlaps
        # another reads every lethal cell that can reach it, so each is complete on its own.
        redos = []
        for group in win.groups_of_mask(changed, 2 * reach + 1):
            inner = (group[0] + window[0], group[1] + window[1],
                     group[2] + window[0], group[3] + window[1])
            redo = win.grow(inner, reach, self._info.width, self._info.height)
            self._master[win.slices(redo)] = self._base[win.slices(redo)]
            redos.append(redo)
        for redo in redos:
            self._inflation.update_costs(self._master, redo)
        log.debug("costmap: recomposed window %s (inflated %s)", window, redos)
        return window


def warm_up() -> None:
    """Compile the costmap's numba kernels on tiny inputs (call once at start-up)."""
    obstacle_kernel.warm_up()
    inflation_kernel.warm_up()
    win.warm_up()
