"""The simulated on-board camera: a picture of what the robot faces, rendered from the lidar.

The lidar already measures how far the walls (and people) are around the robot; the camera
shows that as a first-person view: each image column looks along one bearing of its field of
view, and the wall seen there is drawn with a height inversely proportional to its distance
(corrected for the column's angle, so straight walls stay straight) and shaded darker with
distance; nothing within range leaves the column open. A caption gives the view and the time.
The front camera looks ahead, the rear one behind. Frames are PNG (photos) or JPEG (video
frames and network-camera snapshots).
"""

from __future__ import annotations

import io
import math
from collections.abc import Callable

import numpy as np
from PIL import Image, ImageDraw

from polynav.errors import InvalidRequest
from polynav.robot.interface import LaserScan

WIDTH, HEIGHT = 320, 240
FOV = math.radians(90.0)
WALL_HEIGHT = 1.2  # [m] of wall filling the image height at 1 m
VIEWS = {"front": 0.0, "back": math.pi}
FORMATS = {"png": "PNG", "jpeg": "JPEG"}

_WALL = np.array([225, 215, 190], dtype=np.float64)
# Ceiling over floor, the view with no wall in it.
_EMPTY = np.empty((HEIGHT, WIDTH, 3), dtype=np.uint8)
_EMPTY[: HEIGHT // 2] = (200, 205, 215)
_EMPTY[HEIGHT // 2:] = (110, 112, 118)
_ROWS = np.arange(HEIGHT)[:, None]


def render(scan: LaserScan | None, *, heading: float, caption: str) -> Image.Image:
    """The view along ``heading`` [rad, robot frame] as the scan sees it."""
    image = _EMPTY.copy()  # the caption is drawn into it
    if scan is not None and scan.ranges.shape[0]:
        bearings = heading + FOV * (0.5 - (np.arange(WIDTH) + 0.5) / WIDTH)  # left to right
        # The beam nearest each bearing: beams are evenly spaced, so it is arithmetic; a
        # bearing outside a partial sweep sees nothing.
        n = scan.ranges.shape[0]
        offset = bearings - scan.sensor_pose.theta - scan.angle_min
        steps = np.rint(offset / scan.angle_increment).astype(np.int64)
        full = abs(n * scan.angle_increment) >= 2 * math.pi - 1e-6
        index = np.mod(steps, n) if full else np.clip(steps, 0, n - 1)
        ranges = scan.ranges[index].astype(np.float64)
        if not full:
            ranges[(steps < 0) | (steps >= n)] = np.inf
        depth = ranges * np.cos(bearings - heading)
        seen = np.isfinite(depth) & (depth > 0.05)
        safe = np.where(seen, depth, 1.0)
        half = np.where(seen, np.minimum(HEIGHT / 2, 0.5 * HEIGHT * WALL_HEIGHT / safe), 0.0)
        top = (HEIGHT / 2 - half).astype(np.int64)
        bottom = (HEIGHT / 2 + half).astype(np.int64)
        wall = (_ROWS >= top[None, :]) & (_ROWS < bottom[None, :])
        shade = 1.0 / (1.0 + 0.15 * safe)  # farther walls darker
        colours = (_WALL[None, :] * shade[:, None]).astype(np.uint8)  # one per column
        image = np.where(wall[:, :, None], colours[None, :, :], _EMPTY)
    picture = Image.fromarray(image, "RGB")
    ImageDraw.Draw(picture).text((4, 4), caption, fill=(20, 20, 20))
    return picture


def encode(picture: Image.Image, fmt: str) -> bytes:
    """Raises: InvalidRequest: a format other than png and jpeg."""
    if fmt not in FORMATS:
        raise InvalidRequest("format", f"must be one of {sorted(FORMATS)}, got {fmt!r}")
    out = io.BytesIO()
    picture.save(out, FORMATS[fmt], **({"quality": 80} if fmt == "jpeg" else {}))
    return out.getvalue()


class SimCamera:
    """Implements :class:`~polynav.robot.devices.Camera` over the simulated lidar."""

    def __init__(self, scan: Callable[[], LaserScan | None]) -> None:
        self._scan = scan

    def capture(self, now: float, *, view: str = "front", fmt: str = "png") -> bytes:
        """Raises: InvalidRequest: unknown view or format."""
        if view not in VIEWS:
            raise InvalidRequest("topic", f"no {view!r} camera; views: {sorted(VIEWS)}")
        picture = render(self._scan(), heading=VIEWS[view], caption=f"{view} t={now:.1f}s")
        return encode(picture, fmt)
