"""Recovering a lost robot: the global relocalization search, on request and by itself.

The runtime owns one :class:`LostRecovery`. On request (``RobotRuntime.relocalize``, the native
API's ``POST /api/localization/relocalize``) it searches the current map for the latest scan; and
while the tracker reports LOST it does the same every ``retry_period`` seconds of the robot's
clock, so that a robot that was carried away, or got lost in a corridor, finds itself and the
navigator (which holds a goal while localization is lost) goes on. A found pose restarts the
tracker there. The search runs between ticks: 0.1 to 0.3 s of computation on a demo floor
(820 x 500 cells) while the robot stands (a lost robot is held anyway), plus about as much
once per map for the precomputation.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from polynav.errors import NotLocalized
from polynav.geometry import Pose2D
from polynav.mapping.relocalization import Relocalization, RelocalizationConfig, Relocalizer
from polynav.maps.map import Map
from polynav.robot.interface import LaserScan

log = logging.getLogger(__name__)


class LostRecovery:
    """Relocalizes on request and while LOST.

    Args:
        restart: restarts localization at a pose (the runtime's, between ticks).
        retry_period: while LOST, how often [s] the search runs again.
    """

    def __init__(
        self,
        restart: Callable[[Pose2D], None],
        *,
        config: RelocalizationConfig | None = None,
        retry_period: float = 5.0,
    ) -> None:
        self._restart = restart
        self._config = config or RelocalizationConfig()
        self._retry_period = retry_period
        self._relocalizer: tuple[Map, Relocalizer] | None = None
        self._last_try: float | None = None
        self.last: Relocalization | None = None

    def relocalize(self, grid: Map, scan: LaserScan | None) -> Relocalization:
        """Search ``grid`` for ``scan``; restart localization where it is found.

        Raises:
            NotLocalized: no scan yet, or the scan matches nowhere well enough, or several
                places alike.
        """
        if scan is None:
            raise NotLocalized("no scan yet: nothing to relocalize from")
        result = self._for(grid).locate(scan)
        self.last = result
        if result.pose is None:
            raise NotLocalized(
                f"relocalization failed: {result.reason} (best score {result.score:.2f}, "
                f"runner-up {result.runner_up:.2f})"
            )
        self._restart(result.pose)
        return result

    def tick(self, now: float, lost: bool, grid: Map, scan: LaserScan | None) -> None:
        """Called every control period: search again while LOST, every ``retry_period``."""
        if not lost:
            self._last_try = None
            return
        if self._last_try is not None and now - self._last_try < self._retry_period:
            return
        self._last_try = now
        try:
            result = self.relocalize(grid, scan)
        except NotLocalized as exc:
            log.warning("lost, %s; trying again in %g s", exc, self._retry_period)
            return
        log.info("lost robot relocalized at %s (score %.2f)", result.pose, result.score)

    def _for(self, grid: Map) -> Relocalizer:
        if self._relocalizer is None or self._relocalizer[0] is not grid:
            self._relocalizer = (grid, Relocalizer(grid, self._config))
        return self._relocalizer[1]
