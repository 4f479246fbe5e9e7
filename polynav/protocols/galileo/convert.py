"""Galileo's text file formats (galileo-http-b §1.4, 1.5, 1.7, 1.8) to values and back.

* path file: one point per line, ``x y z``;
* target-point file: ``x y z theta errorX errorY direction [name]`` (the name is the rest of the
  line and may be absent or contain spaces; A-2);
* ignore areas: ``x1 y1 x2 y2`` per line;
* virtual walls: ``x y`` per line.

Numbers may be separated by spaces or TABs; blank lines are skipped. A malformed line raises
:class:`~polynav.errors.InvalidRequest` naming the parameter and the line, before anything is
stored. Numbers are written to 15 significant digits, shortest form (``14.3``, ``0``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D, wrap_angle
from polynav.store.route_stops import Box, Point3, StopInput

MAX_LINES = 100_000


def number_text(value: float) -> str:
    """``value`` to 15 significant digits (what a double holds for sure: it keeps every digit
    the vendor's examples have and hides the last-bit noise of angle wrapping, 0.3 for
    0.2999999999999998), shortest form (``1.0`` -> ``1``)."""
    return format(float(value), ".15g")


def _lines(field: str, text: str) -> Iterable[tuple[int, str]]:
    if not isinstance(text, str):
        raise InvalidRequest(field, "must be a string of lines")
    lines = text.splitlines()
    if len(lines) > MAX_LINES:
        raise InvalidRequest(field, f"at most {MAX_LINES} lines")
    for number, line in enumerate(lines, start=1):
        if line.strip():
            yield number, line


def _numbers(field: str, number: int, words: Sequence[str]) -> list[float]:
    out = []
    for word in words:
        try:
            value = float(word)
        except ValueError:
            raise InvalidRequest(field, f"line {number}: {word!r} is not a number") from None
        if not math.isfinite(value):
            raise InvalidRequest(field, f"line {number}: {word!r} is not finite")
        out.append(value)
    return out


def parse_path(text: str) -> list[Point3]:
    """A path file: ``x y z`` per line (``z`` may be left out)."""
    points: list[Point3] = []
    for number, line in _lines("path_data", text):
        words = line.split()
        if len(words) not in (2, 3):
            raise InvalidRequest("path_data", f"line {number}: expected 'x y z', got {line!r}")
        values = _numbers("path_data", number, words)
        points.append((values[0], values[1], values[2] if len(values) == 3 else 0.0))
    return points


def format_path(points: Iterable[Point3]) -> str:
    return "".join(f"{number_text(x)} {number_text(y)} {number_text(z)}\n" for x, y, z in points)


def parse_targets(text: str) -> list[StopInput]:
    """A target-point file: 7 numbers and an optional name per line."""
    stops: list[StopInput] = []
    for number, line in _lines("path_data", text):
        words = line.split(maxsplit=7)
        if len(words) < 7:
            raise InvalidRequest(
                "path_data",
                f"line {number}: expected 'x y z theta errorX errorY direction [name]', "
                f"got {line!r}",
            )
        x, y, z, theta, error_x, error_y, direction = _numbers("path_data", number, words[:7])
        if error_x < 0 or error_y < 0:
            raise InvalidRequest("path_data", f"line {number}: errors must be >= 0")
        if not direction.is_integer():
            raise InvalidRequest("path_data", f"line {number}: direction must be an integer")
        label = words[7].strip() if len(words) == 8 else ""
        stops.append(StopInput(Pose2D(x, y, wrap_angle(theta)), label, z, error_x, error_y,
                               int(direction)))
    return stops


def target_line(pose: Pose2D, z: float, error_x: float, error_y: float, direction: int,
                label: str) -> str:
    numbers = " ".join(number_text(v) for v in (pose.x, pose.y, z, pose.theta, error_x,
                                                 error_y, direction))
    return f"{numbers} {label}\n" if label else f"{numbers}\n"


def parse_areas(text: str) -> list[Box]:
    """Ignore areas: ``x1 y1 x2 y2`` per line."""
    boxes: list[Box] = []
    for number, line in _lines("skip_area", text):
        words = line.split()
        if len(words) != 4:
            raise InvalidRequest("skip_area", f"line {number}: expected 'x1 y1 x2 y2'")
        x1, y1, x2, y2 = _numbers("skip_area", number, words)
        if x1 == x2 or y1 == y2:
            raise InvalidRequest("skip_area", f"line {number}: the box has no area")
        boxes.append((x1, y1, x2, y2))
    return boxes


def format_areas(boxes: Iterable[Box]) -> str:
    return "".join(" ".join(number_text(v) for v in box) + "\n" for box in boxes)


def parse_walls(text: str) -> list[tuple[float, float]]:
    """Virtual-wall points: ``x y`` per line."""
    points: list[tuple[float, float]] = []
    for number, line in _lines("virtual_wall", text):
        words = line.split()
        if len(words) != 2:
            raise InvalidRequest("virtual_wall", f"line {number}: expected 'x y'")
        x, y = _numbers("virtual_wall", number, words)
        points.append((x, y))
    return points


def format_walls(points: Iterable[tuple[float, float]]) -> str:
    return "".join(f"{number_text(x)} {number_text(y)}\n" for x, y in points)
