"""The runtime's status snapshot: what ``GET /api/status`` and every dialect's status read.

Built once per tick (and after a command) from the backend, the navigation stack, the mapping
session and the goal book, so that a status read never waits for the tick or touches the disk.
"""

from __future__ import annotations

import abc

from polynav.errors import NotFound
from polynav.geometry import Pose2D
from polynav.runtime.door_status import DoorsView
from polynav.runtime.goal_commands import GoalFrame
from polynav.runtime.internals import RuntimeParts
from polynav.runtime.mapping_status import MappingStatus
from polynav.runtime.navigation_events import failure_text
from polynav.runtime.status import StatusSnapshot


class StatusReport(RuntimeParts):
    """The runtime's part that builds its :class:`StatusSnapshot`."""

    _mapless: bool

    @abc.abstractmethod
    def _mapping_status(self, now: float) -> MappingStatus | None:
        """The mapping session as the status shows it (mapping commands)."""

    def _load_status(self) -> dict[str, object] | None:
        """The cart or cabin carried, as the status shows it (cart commands)."""
        carts = getattr(self, "carts", None)  # none yet while the runtime is being built
        load = None if carts is None else carts.status()["load"]
        return dict(load) if isinstance(load, dict) else None

    @abc.abstractmethod
    def _route_overlay(self, snapshot: StatusSnapshot) -> StatusSnapshot:
        """The snapshot with a goal on another map's route and lift phase (lift commands)."""

    @abc.abstractmethod
    def _doors_view(self) -> DoorsView:
        """The doors as the status shows them (door commands)."""

    def _build_snapshot(self, now: float) -> StatusSnapshot:
        stack = self._stack
        odometry = self._robot.read_odometry()
        battery = self._robot.read_battery()
        if stack is not None:
            estimate = stack.estimate
            pose, loc_state, quality = estimate.pose, estimate.state.value, estimate.quality
            uncertainty = estimate.uncertainty
        else:
            # Not localized: the simulator's truth, or for a real robot the last pose shown.
            truth = self._place.true_pose()
            last = getattr(self, "_snapshot", None)
            pose = truth if truth is not None else last.pose if last is not None else Pose2D()
            loc_state, quality = "uninitialized", 0.0
            uncertainty = None
        if self._mapping is not None:
            pose = self._mapping.pose
        attempts = self._attempts
        attempt = attempts.attempt
        nav_state = attempt.state.value if attempt is not None else "idle"
        return self._route_overlay(StatusSnapshot(
            mode=self._mode.value,
            map=self._map_name,
            floor=self._place.floor,
            pose=pose,
            linear=float(odometry.twist.linear),
            angular=float(odometry.twist.angular),
            battery_percent=float(battery.percent),
            charging=bool(battery.charging),
            estop_hardware=bool(self._robot.estop_pressed()),
            estop_software=self._software_estop,
            localization_state=loc_state,
            localization_quality=float(quality),
            localization_uncertainty=uncertainty,
            arrival_uncertainty=attempt.arrival_uncertainty if attempt is not None else None,
            navigation_state=nav_state,
            stamp=now,
            attempt_id=attempts.attempt_id,
            goal=attempt.goal if attempt is not None else None,
            goal_point=attempts.attempt_point if attempt is not None else None,
            reason=(failure_text(attempt) if attempt is not None and attempt.reason
                    else None),
            distance_remaining=attempt.distance_remaining if attempt is not None else None,
            retries=attempt.retries if attempt is not None else 0,
            phase=attempt.phase.value if attempt is not None else None,
            patrol_state=self._patrols.state,
            floor_level=self._floor_level(self._place.floor),
            frame=(GoalFrame.ODOM if self._mapless else GoalFrame.MAP).value,
            mapping=self._mapping_status(now),
            doors=self._doors_view(),
            load=self._load_status(),
        ))

    def _floor_level(self, floor: str | None) -> int | None:
        if floor is None:
            return None
        try:
            return self.store.floor(floor).level
        except NotFound:
            return None
