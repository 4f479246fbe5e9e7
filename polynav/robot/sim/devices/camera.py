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

_CEILING = np.array([200, 205, 215], dtype=np.float64)
_FLOOR = np.array([110, 112, 118], dtype=np.float64)
_WALL = np.array([225, 215, 190], dtype=np.float64)


def render(scan: LaserScan | None, *, heading: float, caption: str) -> Image.Image:
    """The view along ``heading`` [rad, robot frame] as the scan sees it."""
    image = np.empty((HEIGHT, WIDTH, 3), dtype=np.float64)
    image[: HEIGHT // 2] = _CEILING
    image[HEIGHT // 2:] = _FLOOR
    if scan is not None and scan.ranges.shape[0]:
        bearings = heading + FOV * (0.5 - (np.arange(WIDTH) + 0.5) / WIDTH)  # left to right
        beams = scan.angles + scan.sensor_pose.theta
        # The beam nearest each bearing (angles wrap).
        diff = np.angle(np.exp(1j * (bearings[:, None] - beams[None, :])))
        nearest = np.argmin(np.abs(diff), axis=1)
        ranges = scan.ranges[nearest].astype(np.float64)
        depth = ranges * np.cos(bearings - heading)
        for col in np.nonzero(np.isfinite(depth) & (depth > 0.05))[0]:
            half = min(HEIGHT / 2, 0.5 * HEIGHT * WALL_HEIGHT / depth[col])
            shade = 1.0 / (1.0 + 0.15 * depth[col])
            top, bottom = int(HEIGHT / 2 - half), int(HEIGHT / 2 + half)
            image[top:bottom, col] = _WALL * shade
    picture = Image.fromarray(np.clip(image, 0, 255).astype(np.uint8), "RGB")
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
