"""The charger's front plate: a flat face with a V notch in its middle, as a lidar sees it.

The plate is described in the *face frame*: its origin is the centre of the flat face, x points
into the dock (the docking direction, the heading a docked robot has), y to the left. The flat
face runs across ``width``; in its middle a notch ``notch_width`` wide goes ``notch_depth`` deep
into the plate, to a vertex on the x axis. A flat wall, a post or a box has no such notch, so
the notch is what tells a charger from the rest of the room; the wings either side of it give
the face's line.

A docked robot stands ``reach`` behind the face (its front touches it): ``reach`` is the body's
front extent, the disk's radius or the polygon's foremost vertex.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.errors import ConfigError
from polynav.footprint import Footprint
from polynav.geometry import Pose2D


@dataclass(frozen=True, slots=True)
class DockShape:
    """The plate's outline [m] (see the module docstring)."""

    width: float = 0.6
    notch_width: float = 0.3
    notch_depth: float = 0.1

    def __post_init__(self) -> None:
        for key in ("width", "notch_width", "notch_depth"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value > 0.0):
                raise ConfigError(f"dock.{key}", f"must be a finite number > 0, got {value!r}")
        if not self.notch_width < self.width:
            raise ConfigError("dock.notch_width", f"must be below the width ({self.width:g})")

    def segments(self) -> npt.NDArray[np.float64]:
        """(4, 4) rows ``x0, y0, x1, y1`` in the face frame, right to left: the right wing,
        the right flank of the notch, its left flank, the left wing."""
        hw, hn, d = 0.5 * self.width, 0.5 * self.notch_width, self.notch_depth
        return np.array([
            [0.0, -hw, 0.0, -hn],
            [0.0, -hn, d, 0.0],
            [d, 0.0, 0.0, hn],
            [0.0, hn, 0.0, hw],
        ], dtype=np.float64)

    def depth_at(self, v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """How deep [m] the surface lies along x at lateral offsets ``v`` (within the width)."""
        hn = 0.5 * self.notch_width
        return np.where(np.abs(v) < hn, self.notch_depth * (1.0 - np.abs(v) / hn), 0.0)


def front_reach(footprint: Footprint) -> float:
    """How far [m] ahead of the base origin the body's front is: where a dock's face meets it."""
    if footprint.is_circle:
        return footprint.radius
    return float(np.max(footprint.vertices[:, 0]))


def face_of(docked: Pose2D, reach: float) -> Pose2D:
    """The face pose of the dock a robot standing at ``docked`` touches."""
    return docked.compose(Pose2D(reach, 0.0, 0.0))


def docked_at(face: Pose2D, reach: float) -> Pose2D:
    """Where a robot stands docked on the dock whose face pose is ``face``."""
    return face.compose(Pose2D(-reach, 0.0, 0.0))


def world_segments(face: Pose2D, shape: DockShape) -> npt.NDArray[np.float64]:
    """The plate's segments (rows ``x0, y0, x1, y1``) in the frame ``face`` is given in."""
    seg = shape.segments()
    c, s = math.cos(face.theta), math.sin(face.theta)
    out = np.empty_like(seg)
    for k in (0, 2):
        x, y = seg[:, k], seg[:, k + 1]
        out[:, k] = face.x + c * x - s * y
        out[:, k + 1] = face.y + s * x + c * y
    return out
