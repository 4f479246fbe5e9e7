"""Robots simulated elsewhere, as moving bodies in this process's scene.

A site's robots may be simulated in several processes (``polynav bench fleet --transport mqtt
--processes P``); each process steps only its own bodies, yet they share one building. Every
process hears the others' robots (their VDA 5050 ``visualization`` or ``state`` messages, read
by the house, :mod:`polynav.house.remote_robots`) and puts them in its scene through
:class:`RemoteBodies`: a disc per remote robot, on its floor, that the lidars see, that people
stop for, and that a local body moving into is stopped by (a collision with a ``"robot"``).

Where a remote robot is drawn: its last sample, moved on along the velocity that sample gave
for the time since it was taken (dead reckoning), for at most ``max_extrapolation`` seconds; a
sample older than ``max_age`` is no longer drawn (a robot that stopped talking is not a wall for
ever). Moving the last sample on rather than interpolating between the last two keeps the
drawn pose about one sample period fresher: interpolation would draw the robot where it was one
period ago, and a local robot would drive into where it is now (docs/decisions.md).

Pure: samples in, discs out, on the scene's clock; no transport here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

NO_CIRCLES = np.empty((0, 3), dtype=np.float64)


@dataclass(frozen=True, slots=True)
class RemoteSample:
    """Where a remote robot was at ``stamp`` [s of site time], and how it moved then.

    Attributes:
        serial: its serial number.
        floor: the floor it was on.
        x, y, theta: its pose [m, m, rad].
        linear: forward speed [m/s]; omega: turn rate [rad/s].
        stamp: when the sample was taken [s of site time, the sender's clock].
        radius: its body's disc [m].
    """

    serial: str
    floor: str
    x: float
    y: float
    theta: float
    linear: float
    omega: float
    stamp: float
    radius: float


@dataclass(slots=True)
class _Track:
    sample: RemoteSample
    received: float


@dataclass(frozen=True, slots=True)
class Staleness:
    """How old the samples were when they arrived [s of site time]: their count, mean, 99th
    percentile and worst (arrival time minus the sample's own stamp)."""

    samples: int
    mean: float
    p99: float
    worst: float


class RemoteBodies:
    """The robots of the other processes, as discs on their floors (see the module docstring).

    Args:
        max_extrapolation: the longest a sample is moved on along its velocity [s].
        max_age: a sample older than this [s] is not drawn.
    """

    def __init__(self, *, max_extrapolation: float = 1.0, max_age: float = 10.0) -> None:
        self.max_extrapolation = max_extrapolation
        self.max_age = max_age
        self._tracks: dict[str, _Track] = {}
        self._delays: list[float] = []
        self._cache_at: float | None = None
        self._cache: dict[str, npt.NDArray[np.float64]] = {}
        self._serials: dict[str, tuple[str, ...]] = {}

    def update(self, sample: RemoteSample, *, received: float) -> None:
        """Take ``sample``, heard at ``received`` [s of site time, this process's clock]; a
        sample older than the one held for that robot is ignored (QoS 0 may reorder)."""
        held = self._tracks.get(sample.serial)
        if held is not None and sample.stamp < held.sample.stamp:
            return
        self._tracks[sample.serial] = _Track(sample, received)
        self._delays.append(received - sample.stamp)
        self._cache_at = None

    def forget(self, serial: str) -> None:
        """Stop drawing robot ``serial`` (it went offline)."""
        self._tracks.pop(serial, None)
        self._cache_at = None

    @property
    def serials(self) -> tuple[str, ...]:
        """The remote robots heard so far."""
        return tuple(self._tracks)

    def circles(self, floor: str, now: float) -> npt.NDArray[np.float64]:
        """(K, 3) rows of x, y, radius [m]: the remote robots on ``floor`` at ``now``."""
        self._refresh(now)
        return self._cache.get(floor, NO_CIRCLES)

    def serials_on(self, floor: str, now: float) -> tuple[str, ...]:
        """The serials of :meth:`circles`' rows, in order."""
        self._refresh(now)
        return self._serials.get(floor, ())

    def slowest_clock(self) -> float | None:
        """The oldest of the remote robots' latest sample stamps: about where the slowest other
        process's clock stands; None before any sample."""
        if not self._tracks:
            return None
        return min(t.sample.stamp for t in self._tracks.values())

    def staleness(self) -> Staleness:
        """How old samples were on arrival, over every sample so far."""
        if not self._delays:
            return Staleness(0, 0.0, 0.0, 0.0)
        delays = np.asarray(self._delays)
        return Staleness(len(delays), float(delays.mean()), float(np.percentile(delays, 99)),
                         float(delays.max()))

    def _refresh(self, now: float) -> None:
        if self._cache_at == now:
            return
        rows: dict[str, list[tuple[float, float, float]]] = {}
        names: dict[str, list[str]] = {}
        for serial, track in self._tracks.items():
            s = track.sample
            age = now - s.stamp
            if age > self.max_age:
                continue
            x, y = _dead_reckon(s, min(max(age, 0.0), self.max_extrapolation))
            rows.setdefault(s.floor, []).append((x, y, s.radius))
            names.setdefault(s.floor, []).append(serial)
        self._cache = {f: np.array(r, dtype=np.float64) for f, r in rows.items()}
        self._serials = {f: tuple(n) for f, n in names.items()}
        self._cache_at = now


def _dead_reckon(s: RemoteSample, dt: float) -> tuple[float, float]:
    """Where a robot at ``s`` is ``dt`` [s] later, at its sampled speed and turn rate."""
    if dt <= 0.0 or s.linear == 0.0:
        return s.x, s.y
    if abs(s.omega) < 1e-6:
        return s.x + s.linear * dt * math.cos(s.theta), s.y + s.linear * dt * math.sin(s.theta)
    r = s.linear / s.omega
    theta = s.theta + s.omega * dt
    return (s.x + r * (math.sin(theta) - math.sin(s.theta)),
            s.y - r * (math.cos(theta) - math.cos(s.theta)))
