"""Backing out of a pocket: reverse along the way in until the body can turn, then re-plan.

A rectangle that has driven into a dead end narrower than its diagonal cannot turn round in it,
and a route that starts by driving forward cannot leave it: every plan from there fails, and a
recovery that backs up a fixed 0.3 m rarely reaches the mouth. The way the robot came in is the
one way out it knows is free, so it reverses along it (:class:`Trail` keeps the last metres
driven) with pure pursuit steering backwards, the body checked against LETHAL cells before each
step, until it stands where a half turn either way is free (and a margin more), or it has
backed ``max_distance``, or the trail ends. Then the navigator plans again, from a place with
room.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from polynav import footprint as body
from polynav.footprint import Footprint
from polynav.geometry import Pose2D, Twist
from polynav.nav.recoveries import LocalClearing

_TRAIL_SPACING = 0.05  # [m] between recorded poses
_LOOKAHEAD = 0.3  # [m] how far back along the trail the rear steers for
_MIN_BACK = 0.1  # [m] back at least this far before the first turn check can end it
_MARGIN = 0.1  # [m] and this much farther once there is room to turn, to turn with a margin


class Trail:
    """The last ``length`` metres the robot drove, newest last."""

    def __init__(self, length: float = 3.0) -> None:
        self.length = length
        self._poses: deque[Pose2D] = deque(maxlen=max(int(length / _TRAIL_SPACING), 2))

    def clear(self) -> None:
        self._poses.clear()

    def record(self, pose: Pose2D) -> None:
        if not self._poses or self._poses[-1].distance_to(pose) >= _TRAIL_SPACING:
            self._poses.append(pose)

    def way_back(self) -> list[Pose2D]:
        """The trail newest first: the way out, in the order the robot reverses along it."""
        return list(reversed(self._poses))


class BackOut:
    """Reverse along the trail until a half turn is free (module docstring)."""

    name = "back out"

    def __init__(
        self,
        costmap: LocalClearing,
        trail: Trail,
        *,
        footprint: Footprint,
        max_distance: float = 2.0,
        speed: float = 0.2,
        timeout: float = 20.0,
        allowed: bool = True,
    ) -> None:
        self._costmap = costmap
        self._trail = trail
        self.footprint = footprint
        self.max_distance = max_distance
        self.speed = speed
        self.timeout = timeout
        self.allowed = allowed
        self._way: list[Pose2D] = []
        self._index = 0
        self._origin = Pose2D()
        self._started = 0.0
        self._backed = 0.0
        self._last = Pose2D()
        self._origins: list[Pose2D] = []
        self._room_at: float | None = None

    def reset(self) -> None:
        """A new goal: no back-out tried yet."""
        self._origins.clear()

    def may_start(self, pose: Pose2D) -> bool:
        """May the robot reverse, is there a way back, and has no back-out started here before
        in this goal (a second one from the same place would only repeat the first)?"""
        return self.allowed and len(self._trail.way_back()) > 1 and all(
            o.distance_to(pose) > 0.2 for o in self._origins
        )

    def start(self, pose: Pose2D, now: float) -> None:
        self._origins.append(pose)
        self._way = self._trail.way_back()
        self._index = 0
        self._origin = pose
        self._last = pose
        self._started = now
        self._backed = 0.0
        self._room_at = None

    def can_turn(self, pose: Pose2D) -> bool:
        """Is a half turn free either way at ``pose``? Checked as the controller checks a
        turn: whatever the body touches counts, even where it stands."""
        res = self._costmap.info.resolution
        for turn in (math.pi, -math.pi):
            poses = body.rotation_poses(self.footprint, pose, turn, res)
            if body.first_collision(self.footprint, self._costmap, poses) is None:
                return True
        return False

    def tick(self, pose: Pose2D, now: float) -> Twist | None:
        self._backed += pose.distance_to(self._last)
        self._last = pose
        if self._room_at is None and self._backed >= _MIN_BACK and self.can_turn(pose):
            self._room_at = self._backed
        if (
            self._backed >= self.max_distance
            or now - self._started >= self.timeout
            or (self._room_at is not None and self._backed >= self._room_at + _MARGIN)
        ):
            return None
        target = self._target(pose)
        if target is None:
            return None
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        fx = c * (target.x - pose.x) + s * (target.y - pose.y)
        fy = -s * (target.x - pose.x) + c * (target.y - pose.y)
        if fx > 0.0:
            return None  # the way back lies ahead: nothing left to reverse along
        kappa = 2.0 * fy / max(fx * fx + fy * fy, 1e-9)
        if self._blocked(pose, kappa):
            return None
        return Twist(-self.speed, -self.speed * kappa)

    def _target(self, pose: Pose2D) -> Pose2D | None:
        """The first trail pose at least the lookahead away, past the nearest one."""
        while self._index < len(self._way) and self._way[self._index].distance_to(pose) < 0.05:
            self._index += 1
        for k in range(self._index, len(self._way)):
            if self._way[k].distance_to(pose) >= _LOOKAHEAD:
                return self._way[k]
        return self._way[-1] if self._index < len(self._way) else None

    def _blocked(self, pose: Pose2D, kappa: float) -> bool:
        """Would the body, reversing 10 cm along the arc, touch a LETHAL cell it does not
        touch already?"""
        step = 0.5 * self._costmap.info.resolution
        s = -np.arange(0.0, 0.1 + step, step)
        theta = pose.theta + kappa * s
        if abs(kappa) < 1e-9:
            x = pose.x + s * math.cos(pose.theta)
            y = pose.y + s * math.sin(pose.theta)
        else:
            x = pose.x + (np.sin(theta) - math.sin(pose.theta)) / kappa
            y = pose.y - (np.cos(theta) - math.cos(pose.theta)) / kappa
        poses = np.column_stack((x, y, theta))
        return body.first_collision(self.footprint, self._costmap, poses,
                                    ignore_start=True) is not None
