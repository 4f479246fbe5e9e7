"""The embedded simulator: the default robot backend (DESIGN §5).

:class:`~polynav.robot.sim.simulation.Simulation` runs one robot in a
:class:`~polynav.worlds.world.World` on simulated time; its ``robot`` attribute implements the
:class:`~polynav.robot.interface.Robot` protocol.
"""

from __future__ import annotations

import numpy as np

from polynav.maps.map import MapInfo
from polynav.maps.raycast import cast_rays
from polynav.robot.sim import collision, people_detector


def warm_up() -> None:
    """Compile the simulator's numba kernels on tiny inputs (the runtime calls this at start)."""
    collision.warm_up()
    people_detector.warm_up()
    grid = np.zeros((3, 3), dtype=np.bool_)
    cast_rays(grid, MapInfo(1.0, 3, 3), 1.5, 1.5, np.zeros(1), 1.0)
