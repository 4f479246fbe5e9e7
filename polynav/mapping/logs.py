"""Sensor log readers: recorded 2-D laser scans with the raw odometry at each scan.

Three formats, all described in ``shared/data/slam/README.md``:

* **CARMEN** text logs (``.log``, ``.clf``, plain or gzip): ``FLASER``, ``ROBOTLASER1`` and
  ``RAWLASER1..4`` laser lines, ``ODOM`` odometry lines. The odometry of a scan comes from the
  ``ODOM`` stream (lines with a zero timestamp dropped, sorted by time, linearly interpolated to
  the scan's time), **never** from the pose fields of the laser lines: in the public logs those
  are the corrected poses of some earlier SLAM run, and reading them would be cheating.
* the **Intel JSON** scan files (``{"map": {"<stamp>": {"range": [...], "x", "y", "theta"}}}``),
  whose pose is the raw odometry at the scan;
* the **Mines** (CoreSLAM / BreezySLAM) ``.dat`` format: microsecond stamps, wheel encoder
  ticks and Hokuyo ranges in millimetres.

A scan keeps its timestamp exactly as the log writes it (``stamp_text``), so a trajectory written
from it lines up character for character with the log and its ground-truth relations. A
truncated or corrupt line is skipped and counted in :attr:`SensorLog.skipped_lines`, never a
crash; a log with no usable scan at all raises :class:`~polynav.mapping.errors.EmptyLogError`.

The ``parse_*`` functions are pure (lines or a decoded object in, a :class:`SensorLog` out);
:func:`read_log` is the thin file front that picks the format and opens gzip transparently.
"""

from __future__ import annotations

import gzip
import json
import logging
import math
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from polynav.geometry import Pose2D
from polynav.mapping.errors import EmptyLogError, LogError

log = logging.getLogger(__name__)

# The SICK LMS of the Freiburg logs writes 81.83 to 81.91 m for "no return" (README); anything
# from 80 m on is that code, not a wall.
FLASER_NO_RETURN = 80.0

# Mines / BreezySLAM constants (BreezySLAM examples/mines.py and its URG04LX sensor model).
MINES_TICKS_PER_CYCLE = 2000.0
MINES_WHEEL_RADIUS = 0.077  # [m]
MINES_HALF_AXLE = 0.165  # [m]
MINES_BEAMS = 682
MINES_FIRST_RANGE = 24
MINES_FOV = math.radians(240.0)
MINES_RANGE_MAX = 4.0  # [m]
MINES_EDGE_BEAMS = 70  # BreezySLAM's detection margin: beams at each edge it ignores
MINES_LASER_OFFSET = 0.145  # [m], forward of the wheel axle


@dataclass(frozen=True, slots=True, eq=False)
class ScanRecord:
    """One laser scan with the raw odometry pose at its time.

    Attributes:
        stamp: time [s] (the log's own time base).
        stamp_text: the timestamp exactly as the log writes it.
        odom: raw odometry pose at ``stamp`` (odometry frame).
        ranges: (N,) distances [m]; ``inf`` where the beam had no return.
        angles: (N,) beam angles [rad] in the sensor frame.
        sensor_pose: the laser's mount in the robot frame.
    """

    stamp: float
    stamp_text: str
    odom: Pose2D
    ranges: npt.NDArray[np.float64]
    angles: npt.NDArray[np.float64]
    sensor_pose: Pose2D = Pose2D()


@dataclass(frozen=True, slots=True, eq=False)
class SensorLog:
    """The scans of a log, in log order, and what could not be read.

    Attributes:
        scans: the scans.
        skipped_lines: truncated or corrupt lines (or JSON entries) left out.
        has_odometry: False when the log has no odometry at all (every ``odom`` is the origin).
        source: the format read: ``"carmen"``, ``"json"`` or ``"mines"``.
    """

    scans: tuple[ScanRecord, ...]
    skipped_lines: int
    has_odometry: bool
    source: str

    @property
    def duration(self) -> float:
        """Time [s] from the first scan to the last."""
        if not self.scans:
            return 0.0
        return self.scans[-1].stamp - self.scans[0].stamp


# -- CARMEN ---------------------------------------------------------------------------------------


@dataclass(slots=True)
class _RawScan:
    stamp: float
    stamp_text: str
    ranges: npt.NDArray[np.float64]
    angles: npt.NDArray[np.float64]
    sensor_pose: Pose2D


def _floats(tokens: list[str]) -> list[float]:
    values = [float(t) for t in tokens]
    if not all(math.isfinite(v) for v in values):
        raise ValueError("non-finite value")
    return values


def _count(token: str) -> int:
    n = int(token)
    if n < 0:
        raise ValueError("negative count")
    return n


def flaser_angles(n: int) -> npt.NDArray[np.float64]:
    """Beam angles [rad] of an old-format ``FLASER`` line with ``n`` readings.

    Beam i is at -90° + i·res, res = 180°/n for 180 or 360 beams (the last beam at +89° or
    +89.5°) and 180°/(n - 1) otherwise (181, 361: both ends included), per the CARMEN logger.
    """
    res = math.pi / n if n in (180, 360) else math.pi / max(n - 1, 1)
    return -0.5 * math.pi + res * np.arange(n, dtype=np.float64)


def _ranges(values: list[float], no_return: float) -> npt.NDArray[np.float64]:
    r = np.asarray(values, dtype=np.float64)
    return np.where((r > 0.0) & (r < no_return), r, np.inf)


def _parse_flaser(tokens: list[str], front_offset: float) -> _RawScan:
    n = _count(tokens[1])
    if len(tokens) != 2 + n + 6 + 3:
        raise ValueError("wrong field count")
    values = _floats(tokens[2:2 + n])
    stamp_text = tokens[2 + n + 6]
    return _RawScan(float(stamp_text), stamp_text, _ranges(values, FLASER_NO_RETURN),
                    flaser_angles(n), Pose2D(front_offset, 0.0, 0.0))


def _parse_laser_header(tokens: list[str]) -> tuple[float, float, float, int]:
    start, _fov, res, max_range = _floats(tokens[2:6])
    return start, res, max_range, _count(tokens[8])


def _parse_robotlaser(tokens: list[str]) -> _RawScan:
    start, res, max_range, n = _parse_laser_header(tokens)
    m = _count(tokens[9 + n])
    tail = 9 + n + 1 + m
    if len(tokens) != tail + 6 + 5 + 3:
        raise ValueError("wrong field count")
    values = _floats(tokens[9:9 + n])
    lx, ly, lt, rx, ry, rt = _floats(tokens[tail:tail + 6])
    # Both poses are corrected poses; only their difference, the laser mount, is used.
    mount = Pose2D(lx, ly, lt).relative_to(Pose2D(rx, ry, rt))
    stamp_text = tokens[tail + 11]
    return _RawScan(float(stamp_text), stamp_text, _ranges(values, max_range),
                    start + res * np.arange(n, dtype=np.float64), mount)


def _parse_rawlaser(tokens: list[str]) -> _RawScan:
    start, res, max_range, n = _parse_laser_header(tokens)
    m = _count(tokens[9 + n])
    tail = 9 + n + 1 + m
    if len(tokens) != tail + 3:
        raise ValueError("wrong field count")
    values = _floats(tokens[9:9 + n])
    stamp_text = tokens[tail]
    return _RawScan(float(stamp_text), stamp_text, _ranges(values, max_range),
                    start + res * np.arange(n, dtype=np.float64), Pose2D())


def parse_carmen(lines: Iterable[str]) -> SensorLog:
    """Read a CARMEN log's laser scans and attach the interpolated raw odometry to each.

    Args:
        lines: the log's text lines.

    Returns:
        The scans in log order.

    Raises:
        EmptyLogError: no laser line could be read.
    """
    raw: list[_RawScan] = []
    odom_t: list[float] = []
    odom_xyt: list[tuple[float, float, float]] = []
    skipped = 0
    front_offset = 0.0
    for line in lines:
        tokens = line.split()
        if not tokens or tokens[0].startswith("#"):
            continue
        kind = tokens[0]
        try:
            if kind == "ODOM":
                if len(tokens) != 10:
                    raise ValueError("wrong field count")
                x, y, theta, _tv, _rv, _acc, stamp = _floats(tokens[1:8])
                # ODOM lines stamped 0 repeat a corrected pose of the previous laser line.
                if stamp != 0.0:
                    odom_t.append(stamp)
                    odom_xyt.append((x, y, theta))
            elif kind == "FLASER":
                raw.append(_parse_flaser(tokens, front_offset))
            elif kind == "ROBOTLASER1":
                raw.append(_parse_robotlaser(tokens))
            elif kind.startswith("RAWLASER") and kind[8:] in ("1", "2", "3", "4"):
                raw.append(_parse_rawlaser(tokens))
            elif kind == "PARAM" and len(tokens) >= 3 and tokens[1] == "robot_frontlaser_offset":
                front_offset = _floats(tokens[2:3])[0]
        except (ValueError, IndexError):
            skipped += 1
    if skipped:
        log.warning("skipped %d truncated or corrupt log lines", skipped)
    if not raw:
        raise EmptyLogError(f"no laser scans in the log ({skipped} corrupt lines)")
    stamps = np.array([s.stamp for s in raw])
    has_odometry = bool(odom_t)
    if has_odometry:
        poses = interpolate_odometry(np.asarray(odom_t), np.asarray(odom_xyt), stamps)
    else:
        log.warning("log has no odometry; SLAM will rely on scan matching alone")
        poses = np.zeros((len(raw), 3))
    scans = tuple(
        ScanRecord(s.stamp, s.stamp_text, Pose2D(*p), s.ranges, s.angles, s.sensor_pose)
        for s, p in zip(raw, poses.tolist(), strict=True)
    )
    return SensorLog(scans, skipped, has_odometry, "carmen")


def interpolate_odometry(
    times: npt.NDArray[np.float64], poses: npt.NDArray[np.float64], at: npt.NDArray[np.float64]
) -> npt.NDArray[np.float64]:
    """Odometry poses (M, 3) at times ``at``, linear between samples, clamped at the ends.

    Args:
        times: (N,) sample times [s], in any order (sorted here, stable for equal times).
        poses: (N, 3) sample poses (x [m], y [m], theta [rad]).
        at: (M,) query times [s].
    """
    order = np.argsort(times, kind="stable")
    t = times[order]
    p = poses[order]
    theta = np.unwrap(p[:, 2])
    out = np.empty((at.shape[0], 3))
    out[:, 0] = np.interp(at, t, p[:, 0])
    out[:, 1] = np.interp(at, t, p[:, 1])
    out[:, 2] = np.interp(at, t, theta)
    out[:, 2] = np.arctan2(np.sin(out[:, 2]), np.cos(out[:, 2]))
    return out


# -- Intel JSON -----------------------------------------------------------------------------------


def parse_json_scans(document: Any) -> SensorLog:
    """Read an Intel JSON scan file (``{"map": {stamp: {"range", "x", "y", "theta"}}}``).

    Beam i of n is at -90° + i·180°/n (the README's layout), the laser at the robot centre.

    Raises:
        LogError: the document is not of that shape.
        EmptyLogError: it holds no usable scan.
    """
    if not isinstance(document, dict) or not isinstance(document.get("map"), dict):
        raise LogError('not an Intel scan file: expected {"map": {stamp: scan}}')
    entries: list[tuple[float, str, dict[str, Any]]] = []
    skipped = 0
    for key, value in document["map"].items():
        try:
            entries.append((float(key), str(key), value))
        except ValueError:
            skipped += 1
    entries.sort(key=lambda e: e[0])
    scans = []
    for stamp, key, value in entries:
        try:
            values = _floats([str(v) for v in value["range"]])
            if not values:
                raise ValueError("no ranges")
            odom = Pose2D(*_floats([str(value["x"]), str(value["y"]), str(value["theta"])]))
        except (KeyError, TypeError, ValueError):
            skipped += 1
            continue
        n = len(values)
        angles = -0.5 * math.pi + (math.pi / n) * np.arange(n, dtype=np.float64)
        scans.append(ScanRecord(stamp, key, odom, _ranges(values, FLASER_NO_RETURN), angles))
    if skipped:
        log.warning("skipped %d corrupt scan entries", skipped)
    if not scans:
        raise EmptyLogError(f"no scans in the JSON file ({skipped} corrupt entries)")
    return SensorLog(tuple(scans), skipped, True, "json")


# -- Mines (CoreSLAM / BreezySLAM) ---------------------------------------------------------------


def parse_mines(lines: Iterable[str]) -> SensorLog:
    """Read a Mines ``.dat`` log: odometry from the wheel encoders, Hokuyo ranges in mm.

    Wheel angle = ticks·180/2000 degrees, wheel radius 77 mm, half axle 165 mm, integrated as
    BreezySLAM's vehicle model does (see the comment in the body); the laser sits
    145 mm ahead of the axle, its 682 beams spread over 240° counter-clockwise, 0 mm meaning no
    return, and the 70 beams at each edge are dropped (BreezySLAM's detection margin).

    Raises:
        EmptyLogError: no line could be read.
    """
    stamps: list[str] = []
    ticks: list[tuple[float, float]] = []
    ranges: list[npt.NDArray[np.float64]] = []
    skipped = 0
    for line in lines:
        tokens = line.split()
        if not tokens:
            continue
        try:
            if len(tokens) < MINES_FIRST_RANGE + MINES_BEAMS:
                raise ValueError("truncated")
            stamp = float(tokens[0])
            left, right = _floats(tokens[2:4])
            mm = np.asarray(_floats(tokens[MINES_FIRST_RANGE:MINES_FIRST_RANGE + MINES_BEAMS]))
            if not math.isfinite(stamp):
                raise ValueError("bad stamp")
        except (ValueError, IndexError):
            skipped += 1
            continue
        r = mm / 1000.0
        r = np.where((r > 0.0) & (r <= MINES_RANGE_MAX), r, np.inf)
        r[:MINES_EDGE_BEAMS] = np.inf
        r[-MINES_EDGE_BEAMS:] = np.inf
        stamps.append(tokens[0])
        ticks.append((left, right))
        ranges.append(r)
    if not stamps:
        raise EmptyLogError(f"no scans in the Mines log ({skipped} corrupt lines)")
    angles = -0.5 * MINES_FOV + (MINES_FOV / (MINES_BEAMS - 1)) * np.arange(
        MINES_BEAMS, dtype=np.float64)
    wheel = np.radians(np.asarray(ticks) * (180.0 / MINES_TICKS_PER_CYCLE)) * MINES_WHEEL_RADIUS
    pose = Pose2D()
    scans = []
    mount = Pose2D(MINES_LASER_OFFSET, 0.0, 0.0)
    for k, text in enumerate(stamps):
        if k > 0:
            dl, dr = (float(v) for v in wheel[k] - wheel[k - 1])
            # BreezySLAM's WheeledVehicle.computePoseChange (python/breezyslam/vehicles.py):
            # forward r·(φl + φr) and turn (r / half axle)·(φr − φl), twice the textbook
            # differential drive for these constants. The scans agree with it: matched against
            # each other they travel 45.6 m where this gives 44.5 m and the textbook 22.3 m.
            ds = dl + dr
            dtheta = (dr - dl) / MINES_HALF_AXLE
            # Midpoint integration: the chord of an arc leaves at half the turn.
            pose = pose.compose(Pose2D(ds * math.cos(0.5 * dtheta), ds * math.sin(0.5 * dtheta),
                                       dtheta))
        scans.append(ScanRecord(float(text) * 1e-6, text, pose, ranges[k], angles, mount))
    if skipped:
        log.warning("skipped %d truncated or corrupt log lines", skipped)
    return SensorLog(tuple(scans), skipped, True, "mines")


# -- files ----------------------------------------------------------------------------------------


def _text_lines(path: Path) -> list[str]:
    with path.open("rb") as f:
        magic = f.read(2)
    if magic != b"\x1f\x8b":
        return path.read_text(encoding="utf-8", errors="replace").splitlines()
    lines: list[str] = []
    try:
        with gzip.open(path, "rt", encoding="utf-8", errors="replace") as g:
            for line in g:
                lines.append(line)
    except (OSError, EOFError) as exc:
        # A gzip file cut short (a copy interrupted mid-way) still gives the lines before the
        # cut; the last, partial one is then counted as corrupt by the parser.
        log.warning("%s: compressed stream ends early (%s); reading what came before", path, exc)
    return lines


def read_log(path: str | Path) -> SensorLog:
    """Read a log file in any supported format (gzip or plain).

    The format is chosen by content: a JSON object, a Mines ``.dat`` (rows of 700+ numbers), or
    else CARMEN.

    Raises:
        LogError: the file is missing or unreadable.
        EmptyLogError: it holds no usable scan.
    """
    p = Path(path)
    if not p.is_file():
        raise LogError(f"{p}: no such log file")
    lines = _text_lines(p)
    first = next((ln for ln in lines if ln.strip()), "")
    if first.lstrip().startswith("{"):
        try:
            document = json.loads("\n".join(lines))
        except json.JSONDecodeError as exc:
            raise LogError(f"{p}: invalid JSON: {exc}") from exc
        return parse_json_scans(document)
    tokens = first.split()
    if len(tokens) >= MINES_FIRST_RANGE + MINES_BEAMS and tokens[0].isdigit():
        return parse_mines(lines)
    return parse_carmen(lines)
