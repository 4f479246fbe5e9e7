"""A simulated ONVIF pan-tilt-zoom camera on the robot's network.

The camera stands at a fixed address of the documentation range (nothing is ever sent); it
answers only to its user name and password. Its head moves on the runtime's clock: an absolute
move or a preset runs at ``PAN_SPEED`` (normalized units per second) toward the target, a speed
move runs until told to stop or a limit is reached (pan and tilt in -1..1, zoom in 0..1, the
ONVIF normalized space). Snapshots come from the robot's own camera model, looking where the
head points (pan -1..1 is -180..180 degrees from the robot's heading), as JPEG. Its thermometry
(Hikvision ISAPI shape) reads the room temperature of the environment sensors with a spread
over two measuring rules.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from polynav.errors import InvalidRequest
from polynav.robot.devices import PtzPose
from polynav.robot.interface import LaserScan
from polynav.robot.sim.devices.camera import encode, render

PAN_SPEED = 0.5  # [normalized units / s] of an absolute move
PRESETS = {
    "home": PtzPose(0.0, 0.0, 0.0),
    "left": PtzPose(0.5, 0.0, 0.0),
    "right": PtzPose(-0.5, 0.0, 0.0),
    "back": PtzPose(1.0, 0.0, 0.0),
}


@dataclass(frozen=True, slots=True)
class OnvifAccount:
    username: str = "admin"
    password: str = "polynav"


def _clamp_pose(pose: PtzPose) -> PtzPose:
    return PtzPose(min(1.0, max(-1.0, pose.pan)), min(1.0, max(-1.0, pose.tilt)),
                   min(1.0, max(0.0, pose.zoom)))


class SimPtzCamera:
    """Implements :class:`~polynav.robot.devices.PtzCamera`."""

    def __init__(
        self,
        scan: Callable[[], LaserScan | None],
        *,
        address: tuple[str, int] = ("192.0.2.64", 80),
        account: OnvifAccount = OnvifAccount(),  # noqa: B008 - frozen
    ) -> None:
        self.address = address
        self.account = account
        self._scan = scan
        self._pose = PtzPose(0.0, 0.0, 0.0)
        self._t = 0.0
        self._target: PtzPose | None = None
        self._speed = (0.0, 0.0, 0.0)

    def check_login(self, ip: str, port: int, username: str, password: str) -> None:
        """Raises: InvalidRequest: no camera at ``ip:port`` (empty ``ip``: the first camera
        found), or wrong credentials."""
        if ip and (ip, port) != self.address:
            raise InvalidRequest("ip", f"no ONVIF camera answers at {ip}:{port}")
        if (username, password) != (self.account.username, self.account.password):
            raise InvalidRequest("username", "the camera refused the user name or password")

    def pose(self, now: float) -> PtzPose:
        self._advance(now)
        return self._pose

    def move_to(self, now: float, pose: PtzPose) -> None:
        """Raises: InvalidRequest: a value outside the normalized space."""
        for key, value, low in (("x", pose.pan, -1.0), ("y", pose.tilt, -1.0),
                                ("zoom", pose.zoom, 0.0)):
            if not (math.isfinite(value) and low <= value <= 1.0):
                raise InvalidRequest(key, f"must be in {low:g}..1, got {value!r}")
        self._advance(now)
        self._speed = (0.0, 0.0, 0.0)
        self._target = pose

    def move_speed(self, now: float, pan: float, tilt: float, zoom: float) -> None:
        """Raises: InvalidRequest: a speed outside -1..1."""
        for key, value in (("speed_x", pan), ("speed_y", tilt), ("speed_zoom", zoom)):
            if not (math.isfinite(value) and -1.0 <= value <= 1.0):
                raise InvalidRequest(key, f"must be in -1..1, got {value!r}")
        self._advance(now)
        self._target = None
        self._speed = (pan, tilt, zoom)

    def goto_preset(self, now: float, name: str) -> None:
        """Raises: InvalidRequest: no such preset."""
        if name not in PRESETS:
            raise InvalidRequest("preset", f"no preset {name!r}; presets: {sorted(PRESETS)}")
        self.move_to(now, PRESETS[name])

    def presets(self) -> Mapping[str, PtzPose]:
        return dict(PRESETS)

    def snapshot(self, now: float) -> bytes:
        pose = self.pose(now)
        heading = math.pi * pose.pan
        picture = render(self._scan(), heading=heading,
                         caption=f"onvif pan={pose.pan:.2f} t={now:.1f}s")
        return encode(picture, "jpeg")

    def _advance(self, now: float) -> None:
        dt = max(0.0, now - self._t)
        self._t = max(self._t, now)
        if dt == 0.0:
            return
        if self._target is not None:
            p, t = self._pose, self._target
            step = PAN_SPEED * dt
            self._pose = PtzPose(_toward(p.pan, t.pan, step), _toward(p.tilt, t.tilt, step),
                                 _toward(p.zoom, t.zoom, step))
            if self._pose == t:
                self._target = None
        elif self._speed != (0.0, 0.0, 0.0):
            sx, sy, sz = self._speed
            p = self._pose
            self._pose = _clamp_pose(PtzPose(p.pan + sx * dt, p.tilt + sy * dt,
                                             p.zoom + sz * dt))


def _toward(value: float, target: float, step: float) -> float:
    if abs(target - value) <= step:
        return target
    return value + math.copysign(step, target - value)
