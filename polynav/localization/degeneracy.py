"""Which directions a scan pins the pose down in, and which it does not.

In a corridor every wall the lidar sees faces across it: a match slides along the corridor as
freely as the robot drives, and a tracker that trusts it there drifts wherever the noise takes
it (or, comparing with odometry, takes its own drift for a lost robot). The surface normals at
the scan's endpoints tell the two apart: the translational information of the match is
``H = sum n n^T`` over the endpoints that lie on a surface (Censi's ICP covariance, Gauss-Newton
normal matrix of a point-to-line fit); an eigenvalue of ``H`` small beside the other is a
direction the scan does not constrain. :func:`translation_constraint` computes it from the
likelihood field's distance transform, so it costs a few array lookups per scan.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.localization.likelihood_field import LikelihoodField


@dataclass(frozen=True, slots=True)
class Constraint:
    """The scan's translational information at a pose.

    Attributes:
        strong: the larger eigenvalue of ``H`` (surface points across the best direction).
        weak: the smaller one.
        weak_direction: unit vector (map frame) of the weak direction.
        surface_points: endpoints that lie on a surface (within the inlier distance).
    """

    strong: float
    weak: float
    weak_direction: tuple[float, float]
    surface_points: int

    def degenerate(self, ratio: float) -> bool:
        """Whether the weak direction carries less than ``ratio`` of the strong one."""
        return self.weak < ratio * self.strong


def translation_constraint(
    field: LikelihoodField,
    points: npt.NDArray[np.float64],
    pose: Pose2D,
    *,
    inlier_distance: float,
) -> Constraint:
    """``H`` of ``points`` (robot frame, (N, 2)) placed at ``pose`` on ``field``'s map."""
    info = field.info
    c, s = np.cos(pose.theta), np.sin(pose.theta)
    world = np.column_stack((pose.x + c * points[:, 0] - s * points[:, 1],
                             pose.y + s * points[:, 0] + c * points[:, 1]))
    cells = info.world_to_cells(world)
    ix, iy = cells[:, 0], cells[:, 1]
    height, width = field.distance.shape
    inside = (ix >= 1) & (iy >= 1) & (ix < width - 1) & (iy < height - 1)
    ix, iy = ix[inside], iy[inside]
    d = field.distance
    on_surface = np.abs(d[iy, ix]) <= inlier_distance
    ix, iy = ix[on_surface], iy[on_surface]
    gx = d[iy, ix + 1].astype(np.float64) - d[iy, ix - 1]
    gy = d[iy + 1, ix].astype(np.float64) - d[iy - 1, ix]
    norm = np.hypot(gx, gy)
    usable = norm > 1e-9
    nx, ny = gx[usable] / norm[usable], gy[usable] / norm[usable]
    h = np.array([[np.sum(nx * nx), np.sum(nx * ny)], [np.sum(nx * ny), np.sum(ny * ny)]])
    values, vectors = np.linalg.eigh(h)  # ascending
    # The map's cells are in the map's axes; a rotated origin turns the normals with it.
    oc, os_ = np.cos(info.origin.theta), np.sin(info.origin.theta)
    vx, vy = float(vectors[0, 0]), float(vectors[1, 0])
    weak = (oc * vx - os_ * vy, os_ * vx + oc * vy)
    return Constraint(float(values[1]), float(values[0]), weak, int(usable.sum()))
