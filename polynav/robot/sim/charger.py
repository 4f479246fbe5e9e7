"""The simulated charger: a plate the lidar sees, contacts, an infrared beacon and a data link.

Each charger point of a world floor is a real charger in the simulation (the site's marker for
it may be off: the marker is the operator's, the charger is the world's). A :class:`SimCharger`
is:

- a **body**: the front plate of :class:`~polynav.docking.shape.DockShape`, whose face a docked
  robot's front touches (the face stands the robot's front reach ahead of the charger point).
  The lidar casts its beams against the plate's segments exactly (:func:`segment_ranges`), so a
  scan shows the notch as it is, not as a grid of 5 cm cells would; the base collides with the
  plate as with a wall (:func:`body_clearance`, on points every ``SAMPLE_STEP`` along it);
- **contacts**: they touch while the base stands still within the profile's
  ``charger.distance_tolerance`` and ``heading_tolerance`` of the charger point (the simulator's
  ``docked``);
- an **infrared beacon** on the face: seen by the robot's receiver (at the base's centre, looking
  ahead) within ``BEACON_RANGE`` of the face, inside the beacon's cone of ``BEACON_CONE`` either
  side of the face's normal, the robot facing the face within ``RECEIVER_FOV``;
- a **data link** over the contacts: on contact the charger and the robot exchange frames, and
  only after a valid exchange does the charger switch the current on.

Faults (:meth:`~polynav.robot.sim.simulation.Simulation.inject_fault`) break each part:
``charger_beacon_off`` (the beacon never shines), ``charger_link_invalid`` (every frame fails
its check: the charger never switches on) and ``charger_no_power`` (the mains is off: the
plate, the beacon and the link are there, the contacts carry no current).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.docking.shape import DockShape, face_of, world_segments
from polynav.geometry import Pose2D, angle_diff

BEACON_OFF = "charger_beacon_off"
LINK_INVALID = "charger_link_invalid"
NO_POWER = "charger_no_power"
FAULTS = frozenset({BEACON_OFF, LINK_INVALID, NO_POWER})

BEACON_RANGE = 3.0  # [m] from the face
BEACON_CONE = math.radians(35.0)  # either side of the face's normal
RECEIVER_FOV = math.radians(60.0)  # either side of the robot's heading
SAMPLE_STEP = 0.01  # [m] between the plate's points the body is checked against


@dataclass(frozen=True, slots=True, eq=False)
class SimCharger:
    """One charger of a floor: where a robot stands docked on it, and its plate."""

    pose: Pose2D
    face: Pose2D
    segments: npt.NDArray[np.float64]
    samples: npt.NDArray[np.float64]
    extent: float
    """[m] from the face to the farthest end of the plate's segments: no point of the plate
    is farther from the face."""

    @classmethod
    def at(cls, docked: Pose2D, reach: float, shape: DockShape) -> SimCharger:
        """The charger a robot whose front reaches ``reach`` [m] docks on standing at
        ``docked``."""
        face = face_of(docked, reach)
        segments = world_segments(face, shape)
        ends = np.concatenate((segments[:, :2], segments[:, 2:])) - (face.x, face.y)
        extent = float(np.hypot(ends[:, 0], ends[:, 1]).max()) if ends.shape[0] else 0.0
        return cls(docked, face, segments, _samples(segments), extent)

    def touches(self, pose: Pose2D, distance_tolerance: float, heading_tolerance: float) -> bool:
        """Whether a base standing at ``pose`` has its contacts on this charger's."""
        return (pose.distance_to(self.pose) <= distance_tolerance
                and abs(angle_diff(pose.theta, self.pose.theta)) <= heading_tolerance)

    def beacon_seen(self, pose: Pose2D) -> bool:
        """Whether the beacon's light reaches a receiver at ``pose`` (faults aside)."""
        dx, dy = pose.x - self.face.x, pose.y - self.face.y
        distance = math.hypot(dx, dy)
        if distance > BEACON_RANGE:
            return False
        if distance < 1e-9:
            return True
        # The face's outward normal points against the docking direction.
        outward = self.face.theta + math.pi
        if abs(angle_diff(math.atan2(dy, dx), outward)) > BEACON_CONE:
            return False
        towards = math.atan2(-dy, -dx)
        return abs(angle_diff(towards, pose.theta)) <= RECEIVER_FOV


def segment_ranges(
    x: float,
    y: float,
    angles: npt.NDArray[np.float64],
    segments: npt.NDArray[np.float64],
    max_range: float,
) -> npt.NDArray[np.float64]:
    """Distance [m] from (x, y) along each world angle [rad] to the first segment it meets
    (rows ``x0, y0, x1, y1``); ``inf`` where a beam meets none within ``max_range``."""
    if segments.shape[0] == 0:
        return np.full(angles.shape[0], np.inf)
    ux, uy = np.cos(angles)[:, None], np.sin(angles)[:, None]
    ax, ay = segments[None, :, 0] - x, segments[None, :, 1] - y
    ex = segments[None, :, 2] - segments[None, :, 0]
    ey = segments[None, :, 3] - segments[None, :, 1]
    denom = ux * ey - uy * ex
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (ax * ey - ay * ex) / denom  # along the beam
        s = (ax * uy - ay * ux) / denom  # along the segment, 0..1
    hit = (np.abs(denom) > 1e-12) & (t > 0.0) & (s >= 0.0) & (s <= 1.0) & (t <= max_range)
    nearest: npt.NDArray[np.float64] = np.where(hit, t, np.inf).min(axis=1)
    return nearest


def body_clearance(
    pose: Pose2D,
    radius: float,
    polygon: tuple[tuple[float, float], ...],
    chargers: tuple[SimCharger, ...],
) -> float:
    """Signed gap [m] between the base at ``pose`` (a disk of ``radius``, or ``polygon`` in the
    base frame) and the chargers' plates: negative where a plate's point is inside the body;
    ``inf`` with no plate within reach."""
    near = [c.samples for c in chargers
            if math.hypot(c.face.x - pose.x, c.face.y - pose.y) <= radius + 1.0]
    if not near:
        return math.inf
    return points_clearance(pose, radius, polygon, np.concatenate(near))


def points_clearance(
    pose: Pose2D,
    radius: float,
    polygon: tuple[tuple[float, float], ...],
    pts: npt.NDArray[np.float64],
) -> float:
    """Signed gap [m] between the base at ``pose`` (a disk of ``radius``, or ``polygon`` in the
    base frame) and world points ``pts`` (rows x, y): negative where a point is inside the body;
    ``inf`` with no points."""
    if pts.shape[0] == 0:
        return math.inf
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    dx, dy = pts[:, 0] - pose.x, pts[:, 1] - pose.y
    bx, by = c * dx + s * dy, -s * dx + c * dy
    if not polygon:
        return float(np.min(np.hypot(bx, by))) - radius
    poly = np.asarray(polygon, dtype=np.float64)
    ax, ay = poly[:, 0], poly[:, 1]
    ex, ey = np.roll(ax, -1) - ax, np.roll(ay, -1) - ay
    qx, qy = bx[:, None] - ax, by[:, None] - ay
    t = np.clip((qx * ex + qy * ey) / (ex * ex + ey * ey), 0.0, 1.0)
    distance = np.hypot(qx - t * ex, qy - t * ey).min(axis=1)
    # Crossing number: an edge straddling the point's y, crossed to the point's right.
    straddles = (ay <= by[:, None]) != (ay + ey <= by[:, None])
    with np.errstate(divide="ignore", invalid="ignore"):
        cross_x = ax + (by[:, None] - ay) * ex / ey
    inside = (np.count_nonzero(straddles & (cross_x > bx[:, None]), axis=1) % 2) == 1
    return float(np.min(np.where(inside, -distance, distance)))


def _samples(segments: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Points every ``SAMPLE_STEP`` along the segments, their ends included."""
    out = []
    for x0, y0, x1, y1 in segments:
        n = max(1, math.ceil(math.hypot(x1 - x0, y1 - y0) / SAMPLE_STEP))
        t = np.linspace(0.0, 1.0, n + 1)
        out.append(np.stack((x0 + t * (x1 - x0), y0 + t * (y1 - y0)), axis=1))
    return np.concatenate(out)
