"""The status snapshot: the robot's whole state at one instant, as ``GET /api/status`` shows it.

The runtime rebuilds one :class:`StatusSnapshot` per control tick and swaps it in with a single
reference assignment, so a reader on any thread gets a consistent picture in O(1) and never
waits for the tick loop. Adapters format it in their dialects; :meth:`StatusSnapshot.to_dict`
is the native API's JSON, with exactly the keys of issue 3's contract.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

from polynav.geometry import Pose2D
from polynav.localization.interface import PoseUncertainty
from polynav.runtime.door_status import DoorsView
from polynav.runtime.events import pose_dict
from polynav.runtime.mapping_status import MappingStatus

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class StatusSnapshot:
    """The robot's state at ``stamp`` [s] on the runtime's clock.

    Attributes:
        mode: ``"free"``, ``"mapping"``, ``"navigating"`` or ``"busy"``.
        map: the map navigation runs on, ``None`` while not navigating.
        floor: the floor the robot is on; ``floor_level`` its level in the site (``None`` when
            the site has no such floor), read at ``stamp`` like the rest, so that status
            readers (every dialect shows the level) never reach for the store.
        pose: the localization estimate on ``map`` while navigating; otherwise the robot's pose
            on its floor's map (the simulator's ground truth, or odometry on a real robot).
        frame: the frame ``pose`` and the goal are in: ``"map"`` (on a map: ``map`` while
            navigating, the map being built while mapping, the floor's map otherwise) or
            ``"odom"`` (navigating without a map: the odometry frame, (0, 0, 0) where the robot
            was switched on).
        linear, angular: measured velocity [m/s, rad/s].
        battery_percent: charge [%]; ``charging`` while on a charger.
        estop_hardware, estop_software: the button and the software e-stop.
        localization_state: ``"uninitialized"``, ``"tracking"`` or ``"lost"``.
        localization_quality: scan-to-map fit in [0, 1].
        localization_uncertainty: the estimate's uncertainty (position [m] along its worst
            direction, heading [rad], one standard deviation), ``None`` when not known.
        arrival_uncertainty: the same at the current or last attempt's arrival, if it arrived.
        navigation_state: ``idle``, ``running``, ``paused``, ``succeeded``, ``failed``,
            ``canceled`` (of the current or last attempt).
        attempt_id: the current or last attempt's id, if any.
        goal, goal_point: that attempt's goal and the point it was named by.
        reason: why it failed (a :class:`~polynav.nav.attempt.FailureReason` value), if it did.
        distance_remaining: path length [m] still to go, when known.
        retries: that attempt's retries so far (re-plans after a failure).
        phase: that attempt's phase (``leave_charger``, ``navigate``, ``dock``).
        patrol_state: the current or last patrol's state (``running``, ``succeeded``,
            ``failed``, ``canceled``); ``None`` when the last task was a single goal.
        mapping: the mapping session (exploration, mapped area, save job) while mapping or
            while a stop job finishes the map; ``None`` otherwise.
        doors: the door the robot waits at, those it passes, its floor's doors' states.
    """

    mode: str
    map: str | None
    floor: str | None
    pose: Pose2D
    linear: float
    angular: float
    battery_percent: float
    charging: bool
    estop_hardware: bool
    estop_software: bool
    localization_state: str
    localization_quality: float
    navigation_state: str
    stamp: float
    attempt_id: int | None = None
    goal: Pose2D | None = None
    goal_point: str | None = None
    reason: str | None = None
    distance_remaining: float | None = None
    retries: int = 0
    phase: str | None = None
    patrol_state: str | None = None
    floor_level: int | None = None
    localization_uncertainty: PoseUncertainty | None = None
    arrival_uncertainty: PoseUncertainty | None = None
    route: dict[str, object] | None = None
    """A goal on another map: its legs and lift phase (``route_run.status_dict``)."""
    frame: str = "map"
    mapping: MappingStatus | None = None
    doors: DoorsView | None = None
    load: dict[str, object] | None = None
    """The cart or cabin the robot carries (name, kind, mass), if any."""

    def to_dict(self) -> dict[str, object]:
        """The ``GET /api/status`` body (JSON-ready)."""
        goal: dict[str, object] | None = None
        if self.goal is not None:
            goal = {**pose_dict(self.goal), "point": self.goal_point}
        out: dict[str, object] = {
            "mode": self.mode,
            "map": self.map,
            "floor": self.floor,
            "floor_level": self.floor_level,
            "pose": pose_dict(self.pose),
            "frame": self.frame,
            "velocity": {"linear": float(self.linear), "angular": float(self.angular)},
            "battery": {"percent": float(self.battery_percent), "charging": self.charging},
            "estop": {"hardware": self.estop_hardware, "software": self.estop_software},
            "localization": {
                "state": self.localization_state,
                "quality": float(self.localization_quality),
                "uncertainty": uncertainty_dict(self.localization_uncertainty),
            },
            "navigation": {
                "state": self.navigation_state,
                "goal": goal,
                "reason": self.reason,
                "distance_remaining": (
                    None if self.distance_remaining is None else float(self.distance_remaining)
                ),
                "phase": self.phase,
                "retries": int(self.retries),
                "arrival_uncertainty": uncertainty_dict(self.arrival_uncertainty),
            },
            "mapping": None if self.mapping is None else self.mapping.to_dict(),
            "stamp": float(self.stamp),
        }
        if self.doors is not None:
            out["doors"] = self.doors.to_dict()
        if self.load is not None:
            out["load"] = dict(self.load)
        if self.route is not None:
            navigation = out["navigation"]
            assert isinstance(navigation, dict)
            navigation["route"] = self.route
        return out


def uncertainty_dict(uncertainty: PoseUncertainty | None) -> dict[str, float] | None:
    """``{"position": m, "heading": rad}`` (standard deviations), or ``None``: not known."""
    if uncertainty is None:
        return None
    return {"position": float(uncertainty.position), "heading": float(uncertainty.heading)}
