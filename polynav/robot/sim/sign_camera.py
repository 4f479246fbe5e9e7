"""A simulated sign camera: the "no entry" signs of the robot's floor it can see now.

A sign is seen when it stands within the camera's range and field of view (centred on the
base's heading), its face turned towards the robot (within 90 degrees: a board seen from behind
or edge-on says nothing), and the line from the robot to it free of walls on the ground truth.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.maps.map import MapInfo
from polynav.robot.interface import SignDetection
from polynav.worlds.world import NoEntrySign


def seen_signs(robot: Pose2D, signs: tuple[NoEntrySign, ...], *, reach: float, fov: float,
               occupied: npt.NDArray[np.bool_], info: MapInfo) -> list[SignDetection]:
    """The signs a camera of ``reach`` [m] and ``fov`` [rad] on ``robot`` sees, robot frame."""
    out = []
    c, s = math.cos(robot.theta), math.sin(robot.theta)
    for sign in signs:
        dx, dy = sign.x - robot.x, sign.y - robot.y
        distance = math.hypot(dx, dy)
        if distance > reach or distance < 1e-6:
            continue
        bearing = math.atan2(dy, dx) - robot.theta
        if abs(math.atan2(math.sin(bearing), math.cos(bearing))) > 0.5 * fov:
            continue
        # The face looks towards the robot: the way from the sign to the robot is within 90
        # degrees of the way it faces.
        if math.cos(sign.theta) * -dx + math.sin(sign.theta) * -dy <= 0.0:
            continue
        if _blocked(robot.x, robot.y, sign.x, sign.y, occupied, info):
            continue
        out.append(SignDetection(c * dx + s * dy, -s * dx + c * dy))
    return out


def _blocked(x0: float, y0: float, x1: float, y1: float, occupied: npt.NDArray[np.bool_],
             info: MapInfo) -> bool:
    """Whether a wall cell lies on the line between the two points (the sign's own cell, in a
    doorway's edge, does not count)."""
    distance = math.hypot(x1 - x0, y1 - y0)
    steps = max(2, int(distance / (0.5 * info.resolution)))
    t = np.linspace(0.0, 1.0, steps)[:-2]
    xs = np.floor((x0 + t * (x1 - x0) - info.origin.x) / info.resolution).astype(np.int64)
    ys = np.floor((y0 + t * (y1 - y0) - info.origin.y) / info.resolution).astype(np.int64)
    inside = (xs >= 0) & (ys >= 0) & (xs < info.width) & (ys < info.height)
    return bool(np.any(occupied[ys[inside], xs[inside]]))
