"""Global planners by name (STYLE R2: configuration picks implementations through a dict).

Each entry builds a :class:`~polynav.planning.interface.GlobalPlanner` from a
:class:`~polynav.planning.grid_planner.GridPlannerConfig`; the name decides the search, so a
configuration file can say ``planner: theta_star`` without knowing any class. :func:`warm_up`
compiles every numba kernel the planners use, so the first plan after start-up is not the one
that pays for compilation.
"""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Callable

from polynav.errors import ConfigError
from polynav.footprint import Footprint
from polynav.planning import astar, heap, lattice, line_of_sight, smoothing, theta_star
from polynav.planning.footprint_planner import FootprintPlanner, LatticeConfig
from polynav.planning.grid_planner import GridPlanner, GridPlannerConfig
from polynav.planning.interface import GlobalPlanner

log = logging.getLogger(__name__)

PlannerFactory = Callable[[GridPlannerConfig], GlobalPlanner]


def _grid(algorithm: str) -> PlannerFactory:
    def build(config: GridPlannerConfig) -> GlobalPlanner:
        return GridPlanner(dataclasses.replace(config, algorithm=algorithm))

    return build


PLANNERS: dict[str, PlannerFactory] = {
    "astar": _grid("astar"),
    "theta_star": _grid("theta_star"),
}
"""Planner factories by name."""


def create(name: str, config: GridPlannerConfig | None = None) -> GlobalPlanner:
    """The planner registered as ``name``, built with ``config`` (defaults if None).

    Raises:
        ConfigError: no planner has that name.
    """
    factory = PLANNERS.get(name)
    if factory is None:
        raise ConfigError("planner.name", f"{name!r} is not one of {', '.join(sorted(PLANNERS))}")
    return factory(config or GridPlannerConfig())


def for_footprint(
    footprint: Footprint,
    config: GridPlannerConfig | None = None,
    lattice: LatticeConfig | None = None,
) -> GlobalPlanner:
    """The planner for a body: the grid planner for a disk (inflation by its radius is exact
    for every heading), the footprint-checking planner for a polygon
    (:mod:`~polynav.planning.footprint_planner`, its search set by ``lattice``), whose width
    and diagonal differ."""
    config = config or GridPlannerConfig()
    if footprint.vertices.shape[0] == 0:
        return GridPlanner(config)
    return FootprintPlanner(footprint, config, lattice)


def warm_up() -> None:
    """Compile every planning kernel on tiny inputs (seconds the first time, then cached)."""
    heap.warm_up()
    line_of_sight.warm_up()
    astar.warm_up()
    theta_star.warm_up()
    smoothing.warm_up()
    lattice.warm_up()
    log.debug("planning kernels compiled")
