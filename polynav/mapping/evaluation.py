"""The relation error of a SLAM trajectory (Kümmerle et al., "On measuring the accuracy of SLAM
algorithms", Autonomous Robots 27(4), 2009).

A relation ``(t1, t2, δ*)`` is the true motion of the robot from ``t1`` to ``t2`` expressed in
the robot's frame at ``t1``: ``δ* = x(t1)⁻¹ ⊕ x(t2)``. The estimate gives ``δ = x̂(t1)⁻¹ ⊕ x̂(t2)``
and the error is, as in Cartographer's ``compute_relations_metrics`` (so numbers compare with
Cartographer's), ``e = δ · (δ*)⁻¹``; its translational part is ``‖trans(e)‖`` [m] and its
rotational part ``|angle(e)|`` [deg]. Only relative motions are compared, so no alignment of the
trajectory to any global frame is needed.

A pose at a relation's timestamp is the trajectory's own pose when a trajectory stamp lies within
``tolerance`` of it ("exact"), and otherwise is interpolated linearly between the two
neighbouring poses, clamped at the ends (Cartographer's transform interpolation buffer).

Parsing (:func:`parse_trajectory`, :func:`parse_relations`) works on text lines; nothing here
opens files.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.mapping.errors import RelationsError

# Relation and scan stamps are written with 6 decimals; two stamps this close are the same scan.
EXACT_TOLERANCE = 1e-4  # [s]


@dataclass(frozen=True, slots=True)
class Relations:
    """Ground-truth relations, one row each.

    Attributes:
        t1: (N,) first timestamps [s].
        t2: (N,) second timestamps [s].
        delta: (N, 3) true motion (x [m], y [m], theta [rad]) from t1 to t2 in the t1 frame.
    """

    t1: npt.NDArray[np.float64]
    t2: npt.NDArray[np.float64]
    delta: npt.NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class RelationError:
    """Mean and sample standard deviation of the relation errors.

    Attributes:
        relations: relations scored.
        exact: of those, relations whose both stamps hit a trajectory stamp exactly.
        skipped: relations left out (``exact_only`` and not exact).
        trans_mean, trans_std: translational error [m].
        trans2_mean, trans2_std: squared translational error [m²].
        rot_mean, rot_std: rotational error [deg].
        rot2_mean, rot2_std: squared rotational error [deg²].
    """

    relations: int
    exact: int
    skipped: int
    trans_mean: float
    trans_std: float
    trans2_mean: float
    trans2_std: float
    rot_mean: float
    rot_std: float
    rot2_mean: float
    rot2_std: float

    def as_dict(self) -> dict[str, float | int]:
        return {name: getattr(self, name) for name in self.__dataclass_fields__}


def parse_trajectory(
    lines: Iterable[str],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Read ``timestamp x y theta`` lines (``#`` comments and blank lines ignored).

    Returns:
        (N,) times [s] sorted ascending, and (N, 3) poses.

    Raises:
        RelationsError: a line does not have four numbers, or there is no pose.
    """
    rows = _rows(lines, 4, "trajectory")
    if not rows:
        raise RelationsError("trajectory: no poses")
    data = np.asarray(rows, dtype=np.float64)
    order = np.argsort(data[:, 0], kind="stable")
    return data[order, 0], data[order, 1:4]


def parse_relations(lines: Iterable[str]) -> Relations:
    """Read a Freiburg ``.relations`` file: ``t1 t2 x y z roll pitch yaw`` per line.

    Raises:
        RelationsError: a line does not have eight numbers, or there is no relation.
    """
    rows = _rows(lines, 8, "relations")
    if not rows:
        raise RelationsError("relations: none")
    data = np.asarray(rows, dtype=np.float64)
    return Relations(data[:, 0], data[:, 1], data[:, [2, 3, 7]])


def _rows(lines: Iterable[str], width: int, what: str) -> list[list[float]]:
    rows = []
    for number, line in enumerate(lines, start=1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        fields = text.split()
        try:
            values = [float(f) for f in fields]
        except ValueError:
            values = []
        if len(values) != width or not all(math.isfinite(v) for v in values):
            raise RelationsError(f"{what} line {number}: expected {width} numbers, got {text!r}")
        rows.append(values)
    return rows


def poses_at(
    times: npt.NDArray[np.float64], poses: npt.NDArray[np.float64], at: npt.NDArray[np.float64]
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """Trajectory poses at times ``at``, and whether each was exact (a stamp within tolerance).

    Between stamps the pose is interpolated linearly (heading along the shorter arc); outside
    the trajectory it is clamped to the end poses.
    """
    n = times.shape[0]
    idx = np.clip(np.searchsorted(times, at), 1, max(n - 1, 1))
    lo = np.maximum(idx - 1, 0)
    hi = np.minimum(idx, n - 1)
    near = np.where(np.abs(times[lo] - at) <= np.abs(times[hi] - at), lo, hi)
    exact = np.abs(times[near] - at) <= EXACT_TOLERANCE
    span = times[hi] - times[lo]
    w = np.where(span > 0.0, (at - times[lo]) / np.where(span > 0.0, span, 1.0), 0.0)
    w = np.clip(w, 0.0, 1.0)
    dtheta = np.arctan2(np.sin(poses[hi, 2] - poses[lo, 2]), np.cos(poses[hi, 2] - poses[lo, 2]))
    out = np.empty((at.shape[0], 3))
    out[:, :2] = poses[lo, :2] + w[:, None] * (poses[hi, :2] - poses[lo, :2])
    out[:, 2] = poses[lo, 2] + w * dtheta
    out[exact] = poses[near[exact]]
    return out, exact


def relative(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Row-wise ``a⁻¹ ⊕ b`` of (N, 3) poses."""
    c, s = np.cos(a[:, 2]), np.sin(a[:, 2])
    dx, dy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    out = np.empty_like(a)
    out[:, 0] = c * dx + s * dy
    out[:, 1] = -s * dx + c * dy
    out[:, 2] = np.arctan2(np.sin(b[:, 2] - a[:, 2]), np.cos(b[:, 2] - a[:, 2]))
    return out


def compose(a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Row-wise ``a ⊕ b`` of (N, 3) poses."""
    c, s = np.cos(a[:, 2]), np.sin(a[:, 2])
    out = np.empty_like(a)
    out[:, 0] = a[:, 0] + c * b[:, 0] - s * b[:, 1]
    out[:, 1] = a[:, 1] + s * b[:, 0] + c * b[:, 1]
    out[:, 2] = np.arctan2(np.sin(a[:, 2] + b[:, 2]), np.cos(a[:, 2] + b[:, 2]))
    return out


def inverse(a: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Row-wise inverse of (N, 3) poses."""
    return relative(a, np.zeros_like(a))


def relation_error(
    times: npt.NDArray[np.float64],
    poses: npt.NDArray[np.float64],
    relations: Relations,
    *,
    time_offset: float = 0.0,
    exact_only: bool = False,
) -> RelationError:
    """Score a trajectory against relations (Kümmerle et al. 2009, Cartographer's convention).

    Args:
        times: (N,) trajectory stamps [s], ascending.
        poses: (N, 3) trajectory poses.
        relations: the ground truth.
        time_offset: added to the trajectory stamps first [s] (a log in relative time scored
            against relations in absolute time).
        exact_only: score only relations whose both stamps are trajectory stamps.

    Returns:
        The error statistics.

    Raises:
        RelationsError: no relation left to score.
    """
    t = times + time_offset
    p1, exact1 = poses_at(t, poses, relations.t1)
    p2, exact2 = poses_at(t, poses, relations.t2)
    exact = exact1 & exact2
    keep = exact if exact_only else np.ones_like(exact)
    if not keep.any():
        raise RelationsError("no relation matches the trajectory's timestamps")
    estimate = relative(p1[keep], p2[keep])
    e = compose(estimate, inverse(relations.delta[keep]))
    trans = np.hypot(e[:, 0], e[:, 1])
    rot = np.degrees(np.abs(e[:, 2]))

    def stats(v: npt.NDArray[np.float64]) -> tuple[float, float]:
        return float(v.mean()), float(v.std(ddof=1)) if v.shape[0] > 1 else 0.0

    tm, ts = stats(trans)
    t2m, t2s = stats(trans**2)
    rm, rs = stats(rot)
    r2m, r2s = stats(rot**2)
    return RelationError(int(keep.sum()), int(exact[keep].sum()), int((~keep).sum()),
                         tm, ts, t2m, t2s, rm, rs, r2m, r2s)
