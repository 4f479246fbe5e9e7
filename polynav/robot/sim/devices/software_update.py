"""The simulated software updater: the installed version is the newest there is.

An offline simulator has no update server, so a check always finds nothing, starting an update
is refused, and the log says so. A real backend implements
:class:`~polynav.robot.devices.SoftwareUpdate` against its vendor's server.
"""

from __future__ import annotations

from polynav.errors import Conflict


class SimSoftwareUpdate:
    """Implements :class:`~polynav.robot.devices.SoftwareUpdate`."""

    def __init__(self, version: str) -> None:
        self.version = version
        self._log: list[str] = []

    def check(self) -> str | None:
        self._log.append(f"checked for updates: {self.version} is the newest version")
        return None

    def start(self) -> None:
        self._log.append("update refused: no update available")
        raise Conflict(f"no update available: {self.version} is the newest version")

    def cancel(self) -> bool:
        return False

    def log(self) -> str:
        return "\n".join(self._log)
