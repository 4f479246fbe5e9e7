"""The simulated robot's wireless card: the site's access points, as the robot receives them.

Signal strength falls with distance (free-space loss from 1 m) and with every wall between the
robot and an access point on its floor (walls counted on the ground truth); access points on
other floors lose a floor's attenuation per level and 3.5 m of height per level; 5 GHz loses a
little more. The strength is reported on the 0-100 scale Wi-Fi tools print (2 x (dBm + 100)),
and a network below 20 (-90 dBm) is out of range. The card remembers the passwords of networks
it joined, and keeps its connection while the network stays in range. Nothing is ever sent: the
IP address is from the documentation range 192.0.2.0/24 (RFC 5737).
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from polynav.errors import InvalidRequest
from polynav.maps.map import MapInfo
from polynav.worlds.world import AccessPoint, World

_REFERENCE_DBM = -35.0  # at 1 m
_WALL_DB = 6.0
_FLOOR_DB = 18.0
_STOREY_HEIGHT = 3.5
_FIVE_GHZ_DB = 5.0
_FLOOR_DBM = -90.0  # weaker is out of range


@dataclass(frozen=True, slots=True)
class VisibleNetwork:
    ssid: str
    signal: int  # 0..100
    frequency: int  # MHz
    security: str


class WirelessCard:
    """Scans, joins and keeps one Wi-Fi network; ``mac`` is the card's address."""

    def __init__(self, world: World, seed: int = 0) -> None:
        self._aps: list[tuple[int, AccessPoint]] = [
            (floor.level, ap) for floor in world.floors for ap in floor.access_points
        ]
        digest = hashlib.sha256(f"polynav-wifi-{seed}".encode()).digest()
        self.mac = "02:" + ":".join(f"{b:02x}" for b in digest[:5])  # locally administered
        self._known: dict[str, str] = {}
        self._active: str | None = None

    def scan(
        self,
        level: int,
        x: float,
        y: float,
        occupied: npt.NDArray[np.bool_],
        info: MapInfo,
    ) -> list[VisibleNetwork]:
        """The networks in range of (x, y) on floor ``level``, strongest first (one entry per
        SSID: the strongest access point)."""
        best: dict[str, VisibleNetwork] = {}
        for ap_level, ap in self._aps:
            storeys = abs(ap_level - level)
            distance = math.hypot(ap.x - x, ap.y - y, storeys * _STOREY_HEIGHT)
            dbm = _REFERENCE_DBM - 20.0 * math.log10(max(distance, 1.0))
            dbm -= storeys * _FLOOR_DB
            if storeys == 0:
                dbm -= _WALL_DB * _walls_between(x, y, ap.x, ap.y, occupied, info)
            if ap.frequency >= 4900:
                dbm -= _FIVE_GHZ_DB
            if dbm < _FLOOR_DBM:
                continue
            signal = int(max(0, min(100, round(2.0 * (dbm + 100.0)))))
            found = VisibleNetwork(ap.ssid, signal, ap.frequency, ap.security)
            if ap.ssid not in best or best[ap.ssid].signal < signal:
                best[ap.ssid] = found
        return sorted(best.values(), key=lambda n: (-n.signal, n.ssid))

    def connect(self, ssid: str, password: str | None, visible: list[VisibleNetwork]) -> None:
        """Join ``ssid`` (in ``visible``); without ``password`` a network joined before.

        Raises:
            InvalidRequest: not in range, no password for a new secured network, a wrong one.
        """
        network = next((n for n in visible if n.ssid == ssid), None)
        if network is None:
            raise InvalidRequest("SSID", f"no network {ssid!r} in range")
        if network.security:
            expected = next(ap.password for _, ap in self._aps if ap.ssid == ssid)
            given = self._known.get(ssid) if password is None else password
            if given is None:
                raise InvalidRequest("password", f"is required: never joined {ssid!r} before")
            if given != expected:
                raise InvalidRequest("password", f"wrong password for {ssid!r}")
            self._known[ssid] = given
        self._active = ssid

    def active(self, visible: list[VisibleNetwork]) -> str | None:
        """The joined network, while it is in range."""
        if self._active is not None and any(n.ssid == self._active for n in visible):
            return self._active
        return None

    def ip_address(self, visible: list[VisibleNetwork]) -> str:
        """The address the network gave the card (``""`` when not connected)."""
        active = self.active(visible)
        if active is None:
            return ""
        host = 10 + hashlib.sha256((self.mac + active).encode()).digest()[0] % 200
        return f"192.0.2.{host}"


def _walls_between(
    x0: float, y0: float, x1: float, y1: float, occupied: npt.NDArray[np.bool_], info: MapInfo
) -> int:
    """How many separate walls the straight line crosses (runs of occupied cells)."""
    length = math.hypot(x1 - x0, y1 - y0)
    steps = max(2, int(length / (0.5 * info.resolution)))
    t = np.linspace(0.0, 1.0, steps)
    xs = np.floor((x0 + t * (x1 - x0) - info.origin.x) / info.resolution).astype(np.int64)
    ys = np.floor((y0 + t * (y1 - y0) - info.origin.y) / info.resolution).astype(np.int64)
    inside = (xs >= 0) & (ys >= 0) & (xs < info.width) & (ys < info.height)
    hits = np.zeros(steps, dtype=bool)
    hits[inside] = occupied[ys[inside], xs[inside]]
    return int(np.count_nonzero(hits[1:] & ~hits[:-1]) + (1 if hits[0] else 0))
