"""The footprint itself: a circle or a simple polygon in the base frame, validated on creation."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.errors import ConfigError
from polynav.footprint.outline import (
    contains,
    point_segment_distance,
    segments_cross,
    self_intersection,
    signed_area,
)
from polynav.geometry import Pose2D

_EPS = 1e-12

@dataclass(frozen=True, slots=True, eq=False)
class Footprint:
    """The shape of the robot in its base frame: a circle or a simple polygon [m].

    Build one with :meth:`circle`, :meth:`polygon` or :meth:`rectangle`; they validate the shape.

    Attributes:
        radius: the circle's radius [m]; 0 for a polygon.
        vertices: (M, 2) polygon vertices in the base frame, counter-clockwise; (0, 2) for a
            circle. Read-only.
        inscribed_radius: distance [m] from the origin to the nearest point of the outline.
        circumscribed_radius: distance [m] from the origin to the farthest point of the outline.
    """

    radius: float
    vertices: npt.NDArray[np.float64]
    inscribed_radius: float
    circumscribed_radius: float

    @classmethod
    def circle(cls, radius: float, *, key: str = "footprint") -> Footprint:
        """A round robot of ``radius`` [m] centred on the base origin.

        Raises:
            ConfigError: ``radius`` is not a finite number > 0 (named ``<key>.radius``).
        """
        if not (math.isfinite(radius) and radius > 0.0):
            raise ConfigError(f"{key}.radius", f"must be a finite number > 0, got {radius!r}")
        empty = np.zeros((0, 2), dtype=np.float64)
        empty.flags.writeable = False
        return cls(float(radius), empty, float(radius), float(radius))

    @classmethod
    def polygon(
        cls, vertices: Sequence[Sequence[float]] | npt.ArrayLike, *, key: str = "footprint"
    ) -> Footprint:
        """A polygonal robot from its outline in the base frame [m], either winding.

        Raises:
            ConfigError: fewer than 3 vertices, a non-finite coordinate, a repeated vertex, a
                zero-area or self-intersecting outline, or an outline that does not contain the
                base origin (named ``<key>.vertices``).
        """
        field = f"{key}.vertices"
        try:
            pts = np.array(vertices, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise ConfigError(field, f"must be a list of [x, y] pairs ({exc})") from exc
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise ConfigError(field, f"must be a list of [x, y] pairs, got shape {pts.shape}")
        m = pts.shape[0]
        if m < 3:
            raise ConfigError(field, f"needs at least 3 vertices, got {m}")
        if not np.all(np.isfinite(pts)):
            raise ConfigError(field, "every coordinate must be finite")
        for i in range(m):
            j = (i + 1) % m
            if math.hypot(*(pts[j] - pts[i])) < 1e-9:
                raise ConfigError(field, f"vertices {i} and {j} coincide")
        crossing = self_intersection(pts)
        if crossing is not None:
            a, b = crossing
            raise ConfigError(field, f"self-intersecting: edge {a} crosses edge {b}")
        area = signed_area(pts)
        if abs(area) < 1e-12:
            raise ConfigError(field, "the outline encloses no area")
        if area < 0.0:
            pts = pts[::-1].copy()  # keep counter-clockwise so "inside" is "left of every edge"
        if not contains(pts, 0.0, 0.0):
            raise ConfigError(field, "must contain the base origin (0, 0)")
        inscribed = min(
            point_segment_distance(0.0, 0.0, *pts[i], *pts[(i + 1) % m]) for i in range(m)
        )
        circumscribed = float(np.max(np.hypot(pts[:, 0], pts[:, 1])))
        pts.flags.writeable = False
        return cls(0.0, pts, float(inscribed), circumscribed)

    @classmethod
    def rectangle(
        cls, length: float, width: float, *, offset_x: float = 0.0, key: str = "footprint"
    ) -> Footprint:
        """A rectangle ``length`` [m] along x by ``width`` [m] along y.

        Args:
            length: extent along the robot's heading [m].
            width: extent across it [m].
            offset_x: how far [m] the rectangle's centre lies ahead of the base origin (a
                differential drive's axle is often behind the centre).
        """
        if not (math.isfinite(length) and length > 0.0):
            raise ConfigError(f"{key}.length", f"must be a finite number > 0, got {length!r}")
        if not (math.isfinite(width) and width > 0.0):
            raise ConfigError(f"{key}.width", f"must be a finite number > 0, got {width!r}")
        hx, hy = 0.5 * length, 0.5 * width
        return cls.polygon(
            [
                (offset_x + hx, hy),
                (offset_x - hx, hy),
                (offset_x - hx, -hy),
                (offset_x + hx, -hy),
            ],
            key=key,
        )

    def padded(self, margin: float) -> Footprint:
        """The body grown by ``margin`` [m] all round (Nav2's ``footprint_padding``): a planner
        leaves this much room either side for control and localization to err in.

        A polygon's edges move out by ``margin`` and meet at new vertices (the mitred offset,
        exact for a convex outline; a concave corner is moved out as far, which may grow it a
        little more there).
        """
        if margin == 0.0:
            return self
        if self.is_circle:
            return Footprint.circle(self.radius + margin)
        pts = self.vertices  # counter-clockwise
        prev = np.roll(pts, 1, axis=0)
        nxt = np.roll(pts, -1, axis=0)

        def normals(d: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
            n = np.column_stack((d[:, 1], -d[:, 0]))  # outward for a counter-clockwise outline
            return np.asarray(n / np.hypot(n[:, 0], n[:, 1])[:, None])

        n_in, n_out = normals(pts - prev), normals(nxt - pts)
        bisector = n_in + n_out
        scale = margin / np.maximum(1.0 + np.sum(n_in * n_out, axis=1), 1e-6)
        return Footprint.polygon(pts + bisector * scale[:, None])

    @property
    def is_circle(self) -> bool:
        return bool(self.vertices.shape[0] == 0)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Footprint):
            return NotImplemented
        return self.radius == other.radius and bool(np.array_equal(self.vertices, other.vertices))

    def __hash__(self) -> int:
        return hash((self.radius, self.vertices.tobytes()))

    def __repr__(self) -> str:
        if self.is_circle:
            return f"Footprint.circle({self.radius!r})"
        return f"Footprint.polygon({self.vertices.tolist()!r})"

    def outline(self, pose: Pose2D, *, segments: int = 32) -> npt.NDArray[np.float64]:
        """The outline (M, 2) [m] placed at ``pose``; a circle as a ``segments``-gon."""
        if self.is_circle:
            a = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)
            local = np.column_stack((self.radius * np.cos(a), self.radius * np.sin(a)))
        else:
            local = self.vertices
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        out = np.empty_like(local)
        out[:, 0] = pose.x + c * local[:, 0] - s * local[:, 1]
        out[:, 1] = pose.y + s * local[:, 0] + c * local[:, 1]
        return out

    def contains_point(self, pose: Pose2D, x: float, y: float) -> bool:
        """True if world point (x, y) [m] lies inside (or on) the footprint placed at ``pose``."""
        local = Pose2D(x, y).relative_to(pose)
        if self.is_circle:
            return math.hypot(local.x, local.y) <= self.radius
        return contains(self.vertices, local.x, local.y)

    def covers(self, other: Footprint) -> bool:
        """True if this footprint contains ``other`` whole (both in the same base frame).

        The planning footprint must cover the body's: a planner that plans for a smaller robot
        sends the body into gaps it does not fit.
        """
        if self.is_circle:
            return other.circumscribed_radius <= self.radius + 1e-9
        if other.is_circle:
            # The disk is centred on the origin, inside this polygon: it fits if no edge is nearer.
            return self.inscribed_radius >= other.radius - 1e-9
        if not all(contains(self.vertices, float(px), float(py)) for px, py in other.vertices):
            return False
        m, k = self.vertices.shape[0], other.vertices.shape[0]
        return not any(
            segments_cross(
                self.vertices[i], self.vertices[(i + 1) % m],
                other.vertices[j], other.vertices[(j + 1) % k],
            )
            for i in range(m)
            for j in range(k)
        )

    def rotation_step(self, resolution: float) -> float:
        """Heading step [rad] at which the farthest point moves at most half a cell.

        Sampling a turn in place this finely checks the swept area, not just its two ends.
        """
        return min(0.5 * resolution / max(self.circumscribed_radius, _EPS), math.pi / 8.0)
