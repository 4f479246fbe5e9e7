"""People around the robot, in the map frame: where they are, where they will be shortly, and
whether they are what blocks the way.

A leg tracker reports people in the robot frame (:class:`~polynav.robot.interface.PersonDetection`);
the navigation stack turns them into a :class:`PeopleView` with the localization estimate each
control period. The navigator uses it three ways: the costmap's people layer keeps plans a social
distance from where people are and will be, the robot slows down near people, and a way blocked
only by people is waited for (patience) instead of being failed as an obstacle would be.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

from polynav.errors import ConfigError, check_positive
from polynav.geometry import Pose2D
from polynav.robot.interface import PersonDetection

_WAY_AHEAD = 4.0  # [m] how far along their walk (or towards the robot) people are expected
_WAY_BEHIND = 1.5  # [m] how far back along their walk a walker's line is still theirs: people
# turn back (a walker shuttling between two doors came back 2 s after a robot stepped onto their
# line behind them, into the doorway they had just left, and both stood there: issue 36, bench
# fleet seed 3)
_SPOT_RINGS = np.arange(0.6, 2.01, 0.2)  # [m] distances of the spots tried to step aside to
_SPOT_BEARINGS = np.linspace(-math.pi, math.pi, 24, endpoint=False)
_SPOT_MAX_COST = 128  # a spot well clear of walls, and outside every person's social disc
_WALKING = 0.1  # [m/s] a person faster than this walks (their way is ahead of them)
_ON_THE_LINE = 0.05  # [m] a robot this near a walker's line is on it (any way leaves it)
_CLEAR_ENOUGH = 1.6  # [m] from everyone's way: farther is no better (then the least turn)
_TURN_RATE = 0.8  # [rad/s] the turn before stepping aside, as expected of the controller
_TRIP_STEP = 0.1  # [s] between the instants of a step-aside played against a walk
_TRIP_MARGIN = 0.1  # [m] beyond the social distance: predictions are from tracked legs


@dataclass(frozen=True, slots=True)
class PeopleConfig:
    """How navigation treats people [m, s, m/s].

    Attributes:
        enabled: use the leg tracker at all.
        social_distance: centre-to-centre distance the robot keeps from people where it can;
            plans avoid it (the people layer) and the robot slows inside it.
        slow_speed: the top speed within ``social_distance`` of a person.
        approach_time: near a person the robot's speed towards them is at most its distance
            beyond the social distance over this time, so it eases to a stop at the edge of
            their space.
        hold_before_wait: kept still that way this long, the robot waits for the people (it
            re-plans round them, and gives way) as when they block the path.
        horizon: how far ahead people's positions are predicted (constant velocity).
        prediction_step: spacing of the predicted positions.
        layer_cost: the cost (1..252) of cells within ``social_distance`` of a person now or
            predicted: high enough that a plan goes round when there is room, not lethal, so
            a person never makes the goal unreachable on the map alone.
        block_radius: a person this close to the path ahead, or to the robot, may be what
            blocks it.
        block_lookahead: how far along the path ahead people are looked for.
        patience: how long the robot waits for people to make way before the goal fails with
            ``blocked by person``.
        wait_replan_period: while waiting, how often another way is looked for.
        give_way_after: while someone stands face to face with the robot this long, it backs
            up ``give_way_distance`` to leave them room to pass (they may be waiting for it).
    """

    enabled: bool = True
    social_distance: float = 0.8
    slow_speed: float = 0.3
    approach_time: float = 0.8
    hold_before_wait: float = 1.0
    horizon: float = 1.0
    prediction_step: float = 0.5
    layer_cost: int = 180
    block_radius: float = 1.0
    block_lookahead: float = 3.0
    patience: float = 60.0
    wait_replan_period: float = 2.0
    give_way_after: float = 5.0
    give_way_distance: float = 0.5

    def __post_init__(self) -> None:
        check_positive(self, "nav.people.", (
            "social_distance", "slow_speed", "approach_time", "hold_before_wait",
            "prediction_step", "block_radius", "block_lookahead", "patience",
            "wait_replan_period", "give_way_after", "give_way_distance"))
        if not (math.isfinite(self.horizon) and self.horizon >= 0.0):
            raise ConfigError("nav.people.horizon", f"must be finite and >= 0, got {self.horizon}")
        if not 1 <= self.layer_cost <= 252:
            raise ConfigError("nav.people.layer_cost", f"must be in 1..252, got {self.layer_cost}")


def densify(points: npt.NDArray[np.float64], step: float) -> npt.NDArray[np.float64]:
    """The polyline ``points`` (N, 2) sampled at most ``step`` apart (any-angle paths have few
    vertices: a person in the middle of a long segment is far from both of its ends)."""
    if points.shape[0] < 2:
        return points
    seg = np.diff(points, axis=0)
    counts = np.maximum(1, np.ceil(np.hypot(seg[:, 0], seg[:, 1]) / step).astype(np.int64))
    t = np.concatenate([np.arange(n) / n for n in counts])
    starts = np.repeat(np.arange(seg.shape[0]), counts)
    samples = points[starts] + seg[starts] * t[:, None]
    return np.vstack([samples, points[-1:]])


@dataclass(frozen=True, slots=True)
class Person:
    """A person in the map frame: position [m], velocity [m/s]."""

    x: float
    y: float
    vx: float = 0.0
    vy: float = 0.0


@dataclass(frozen=True, slots=True)
class PeopleView:
    """The people seen at one control period, in the map frame."""

    people: tuple[Person, ...] = ()

    @classmethod
    def from_detections(cls, detections: Sequence[PersonDetection], pose: Pose2D) -> PeopleView:
        """Detections (robot frame) placed on the map with the robot's estimated ``pose``."""
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        return cls(tuple(
            Person(pose.x + c * d.x - s * d.y, pose.y + s * d.x + c * d.y,
                   c * d.vx - s * d.vy, s * d.vx + c * d.vy)
            for d in detections
        ))

    def __bool__(self) -> bool:
        return bool(self.people)

    def positions(self, horizon: float = 0.0, step: float = 0.5) -> list[tuple[float, float]]:
        """Every person now and at each ``step`` up to ``horizon`` seconds ahead."""
        times = [0.0]
        t = step
        while t <= horizon + 1e-9:
            times.append(t)
            t += step
        return [(p.x + p.vx * t, p.y + p.vy * t) for p in self.people for t in times]

    def nearest(self, x: float, y: float) -> float:
        """Distance [m] from (x, y) to the nearest person, ``inf`` with nobody around."""
        return min((math.hypot(p.x - x, p.y - y) for p in self.people), default=math.inf)

    def near_any(self, points: npt.NDArray[np.float64], radius: float) -> bool:
        """Whether a person stands within ``radius`` of any of ``points`` (shape (N, 2))."""
        if not self.people or points.shape[0] == 0:
            return False
        for p in self.people:
            d2 = (points[:, 0] - p.x) ** 2 + (points[:, 1] - p.y) ** 2
            if float(d2.min()) <= radius * radius:
                return True
        return False


class CostLookup(Protocol):
    def cost_at(self, x: float, y: float) -> int: ...


def _segment_distance(px: float, py: float, ax: float, ay: float, bx: float, by: float) -> float:
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 == 0.0 else max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / length2))
    return math.hypot(px - (ax + t * dx), py - (ay + t * dy))


def aside_spots(
    costmap: CostLookup, pose: Pose2D, people: PeopleView, config: PeopleConfig, *, limit: int = 4
) -> list[Pose2D]:
    """Spots near the robot off the way of the people in front of it, nearest first.

    A person's way is the segment ahead of them along their walk (from a little behind them:
    people turn back, and a spot on their line behind them is in their way then), or, for
    someone standing,
    towards and past the robot (they are likely waiting to come through where it stands). A
    spot is free on the costmap, outside everyone's social disc, at least the social distance
    from every such way, and the straight way to it brings the robot no nearer anyone than the
    social distance (or than it stands now, when nearer); the robot drives there and lets
    them pass.

    A walker keeps coming while the robot steps aside, so where they stand now is not enough:
    the robot's trip (a turn on the spot, then the straight way at the slow speed) is played
    against their straight walk, and a spot is refused when the robot would be closing in on
    them inside their space (plus :data:`_TRIP_MARGIN`) at any instant of it, or when the way
    crosses to the other side of their line ahead of them (stepping across someone's way is
    not leaving it). Of a ring of spots, those farthest from everyone's way come first: the
    side the walker is not heading to.
    """
    ways = []
    for p in people.people:
        if math.hypot(p.x - pose.x, p.y - pose.y) > _WAY_AHEAD:
            continue
        speed = math.hypot(p.vx, p.vy)
        behind = 0.0
        if speed > _WALKING:
            ux, uy = p.vx / speed, p.vy / speed
            behind = _WAY_BEHIND
        else:
            d = math.hypot(pose.x - p.x, pose.y - p.y) or 1.0
            ux, uy = (pose.x - p.x) / d, (pose.y - p.y) / d
        ways.append((p.x - behind * ux, p.y - behind * uy,
                     p.x + _WAY_AHEAD * ux, p.y + _WAY_AHEAD * uy))
    walkers = [p for p in people.people
               if math.hypot(p.vx, p.vy) > _WALKING
               and math.hypot(p.x - pose.x, p.y - pose.y) <= _WAY_AHEAD]
    # Getting there must not bring the robot nearer anyone than the social distance, or than
    # it already is when it stands nearer: stepping aside is to leave room, not to brush by.
    keep = [(p.x, p.y, min(config.social_distance, math.hypot(p.x - pose.x, p.y - pose.y)))
            for p in people.people]
    spots: list[Pose2D] = []
    for ring in _SPOT_RINGS:
        found: list[tuple[float, float, Pose2D]] = []
        for bearing in _SPOT_BEARINGS:
            x = pose.x + float(ring) * math.cos(pose.theta + float(bearing))
            y = pose.y + float(ring) * math.sin(pose.theta + float(bearing))
            if costmap.cost_at(x, y) > _SPOT_MAX_COST:
                continue
            clearance = min((_segment_distance(x, y, *way) for way in ways), default=math.inf)
            if clearance < config.social_distance or not all(
                _segment_distance(px, py, pose.x, pose.y, x, y) >= clear - 1e-6
                for px, py, clear in keep
            ):
                continue
            if any(_crosses(pose, x, y, p) or _closes_in(pose, x, y, p, config)
                   for p in walkers):
                continue
            found.append((-min(clearance, _CLEAR_ENOUGH), abs(float(bearing)),
                          Pose2D(x, y, pose.theta)))
        spots.extend(spot for _, _, spot in sorted(found, key=lambda f: (f[0], f[1])))
        if len(spots) >= limit:
            break
    return spots[:limit]


def _crosses(pose: Pose2D, x: float, y: float, p: Person) -> bool:
    """Whether the straight way from ``pose`` to (x, y) crosses the line of the walker ``p``
    ahead of them, from the robot's side to the other (a robot on their line crosses none)."""
    speed = math.hypot(p.vx, p.vy)
    ux, uy = p.vx / speed, p.vy / speed
    side_now = ux * (pose.y - p.y) - uy * (pose.x - p.x)
    side_spot = ux * (y - p.y) - uy * (x - p.x)
    if abs(side_now) < _ON_THE_LINE or side_now * side_spot > 0.0:
        return False
    # Where the way meets their line: ahead of them is in front of someone walking.
    t = side_now / (side_now - side_spot)
    cx, cy = pose.x + t * (x - pose.x), pose.y + t * (y - pose.y)
    return ux * (cx - p.x) + uy * (cy - p.y) > 0.0


def _closes_in(pose: Pose2D, x: float, y: float, p: Person, config: PeopleConfig) -> bool:
    """Whether stepping from ``pose`` to (x, y) would close in on the walker ``p`` within
    their social distance (plus :data:`_TRIP_MARGIN`) at some instant.

    The trip: a turn on the spot to face (x, y) at :data:`_TURN_RATE`, then the straight way
    at the slow speed; the walker: a straight walk at their velocity. Closing in is the
    robot's own velocity having a component towards them while the gap shrinks (following a
    faster walker who overtook it is not).
    """
    dx, dy = x - pose.x, y - pose.y
    length = math.hypot(dx, dy)
    if length == 0.0:
        return False
    ux, uy = dx / length, dy / length
    turn = abs(math.remainder(math.atan2(dy, dx) - pose.theta, math.tau)) / _TURN_RATE
    t = np.arange(turn, turn + length / config.slow_speed + _TRIP_STEP, _TRIP_STEP)
    along = np.minimum((t - turn) * config.slow_speed, length)
    rx = p.x + p.vx * t - (pose.x + ux * along)
    ry = p.y + p.vy * t - (pose.y + uy * along)
    moving = along < length
    vx, vy = ux * config.slow_speed * moving, uy * config.slow_speed * moving
    near = rx * rx + ry * ry < (config.social_distance + _TRIP_MARGIN) ** 2
    towards = ux * rx + uy * ry > 0.0
    shrinking = rx * (p.vx - vx) + ry * (p.vy - vy) < 0.0
    return bool(np.any(moving & near & towards & shrinking))
