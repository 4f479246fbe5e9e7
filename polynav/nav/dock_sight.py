"""Where the charger really is, over one dock phase: found once near the marker, then followed.

The marker (the site's charger point) says where the robot should stand docked; the charger may
be some centimetres and degrees off it. At the approach the dock phase hands each new scan to a
:class:`DockSight`: the first finds the plate near the marker's face
(:func:`~polynav.docking.detector.find_dock`), the later ones re-detect it from the last pose
(:func:`~polynav.docking.detector.refine_dock`) while the robot drives in, each blended into
the pose held (``BLEND``: one noisy scan moves the target only half way). A scan that does not
show the plate keeps the last pose: close in, the plate may be partly hidden.
"""

from __future__ import annotations

import logging

from polynav.docking.detector import DetectorConfig, find_dock, points_of_scan, refine_dock
from polynav.docking.shape import DockShape, docked_at, face_of
from polynav.geometry import Pose2D, angle_diff
from polynav.robot.interface import LaserScan

log = logging.getLogger(__name__)

BLEND = 0.5


class DockSight:
    """The charger's face pose as seen over one dock phase (map frame)."""

    def __init__(self, reach: float, shape: DockShape | None = None,
                 config: DetectorConfig | None = None) -> None:
        self._reach = reach
        self._shape = shape or DockShape()
        self._config = config or DetectorConfig()
        self._expected = Pose2D()
        self.face: Pose2D | None = None
        self.quality = 0.0

    def reset(self, marker: Pose2D) -> None:
        """Begin a dock phase onto the charger the marker (a docked pose) names."""
        self._expected = face_of(marker, self._reach)
        self.face = None
        self.quality = 0.0

    @property
    def docked_pose(self) -> Pose2D | None:
        """Where the robot should stand docked, as seen; ``None`` until the plate is found."""
        return None if self.face is None else docked_at(self.face, self._reach)

    def see(self, scan: LaserScan, pose: Pose2D) -> bool:
        """Look for the plate in ``scan`` taken at ``pose`` (map frame); whether it was seen."""
        points = points_of_scan(scan, pose)
        if self.face is None:
            found = find_dock(points, self._expected, self._shape, self._config)
            if found is not None:
                self.face, self.quality = found.pose, found.quality
                log.info("charger seen %.3f m, %.3f rad off its marker (quality %.2f)",
                         found.pose.distance_to(self._expected),
                         angle_diff(found.pose.theta, self._expected.theta), found.quality)
            return found is not None
        again = refine_dock(points, self.face, self._shape, self._config,
                            expected=self._expected)
        if again is None:
            return False
        old, new = self.face, again.pose
        self.face = Pose2D(old.x + BLEND * (new.x - old.x), old.y + BLEND * (new.y - old.y),
                           old.theta + BLEND * angle_diff(new.theta, old.theta))
        self.quality = again.quality
        return True
