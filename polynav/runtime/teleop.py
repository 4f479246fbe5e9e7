"""Teleoperation with a dead-man timeout.

A remote operator streams velocity commands; if the stream stops (the app crashed, the network
dropped, the finger left the joystick) the robot must stop by itself. :class:`Teleop` holds the
last command and forgets it ``timeout`` seconds of the runtime's clock after it was given, so the
base brakes to a stand-still without any further message.
"""

from __future__ import annotations

import logging

from polynav.geometry import Twist

log = logging.getLogger(__name__)


class Teleop:
    """The operator's last velocity command and when it expires.

    Args:
        timeout: a command holds this long [s] (0.5 s, as the vendors' joystick APIs document).
    """

    def __init__(self, timeout: float) -> None:
        self.timeout = timeout
        self._twist: Twist | None = None
        self._expires = 0.0

    @property
    def active(self) -> bool:
        """True while a command holds (until the next :meth:`twist` call finds it expired)."""
        return self._twist is not None

    def command(self, twist: Twist, now: float) -> None:
        """A new command at ``now`` [s]; it holds until ``now + timeout``."""
        if self._twist is None:
            log.info("teleop started")
        self._twist = twist
        self._expires = now + self.timeout

    def twist(self, now: float) -> Twist | None:
        """The command to apply at ``now``, or ``None`` when there is none (or it expired)."""
        if self._twist is not None and now >= self._expires - 1e-9:
            log.info("teleop dead-man: no command for %.2f s, stopping", self.timeout)
            self._twist = None
        return self._twist

    def stop(self) -> None:
        """Forget the command at once (e-stop, a goal, navigation stopped)."""
        self._twist = None
