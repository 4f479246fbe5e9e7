"""Compiling the numba kernels a robot ticks before its first tick."""

from __future__ import annotations

from polynav.localization import pose_tracker
from polynav.maps import costmap
from polynav.planning import registry as planning_registry
from polynav.robot import sim as sim_kernels


def warm_up() -> None:
    """Compile (or load from numba's cache) every kernel the runtime ticks, before the first
    tick, so that the first goal is not late by seconds of compilation."""
    costmap.warm_up()
    planning_registry.warm_up()
    pose_tracker.warm_up()
    sim_kernels.warm_up()
