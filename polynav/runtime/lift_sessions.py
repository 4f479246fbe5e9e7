"""Who may use a lift car: the car's session, granted as a lease on ``lift:<car>``.

The lift sequence asks for a car's session before calling it and gives it back once it has left
the car. :class:`LiftSessions` is the seam: a lone robot uses :class:`LocalLiftSessions` (its
own lease book, so it always gets a free car at once); in a building the fleet puts in its own
implementation (:mod:`polynav.fleet.lift_sessions`), which asks the site's lease book through
VDA 5050 zone requests, so that robots queue for a car first come, first served, and a robot
that stops answering loses the car when its lease lapses.
"""

from __future__ import annotations

import logging
from typing import Protocol

from polynav.leases.book import LeaseBook, LeaseBookConfig

log = logging.getLogger(__name__)

SESSION_LEASE = 60.0
"""How long [s] one grant or renewal of a session lasts; renewed while held."""


def resource(car: str, kind: str = "lift") -> str:
    """The lease book's name of car ``car``'s session (of device ``car`` of ``kind``: a door's
    lease is ``door:<name>``)."""
    return f"{kind}:{car}"


class LiftSessions(Protocol):
    """Asking for, holding and giving back cars' sessions, for one robot."""

    def request(self, car: str, now: float, flow: str | None = None) -> None:
        """Ask for ``car``'s session (again: nothing new); renews it while held. ``flow``: the
        way the robot goes through (a door crossed one way), shared with others going that
        way; the first ask's is kept."""
        ...

    def granted(self, car: str, now: float) -> bool:
        """Whether this robot holds ``car``'s session now."""
        ...

    def rejected(self, car: str) -> bool:
        """Whether the last request was turned down (waited too long, revoked): ask again or
        give up."""
        ...

    def release(self, car: str, now: float) -> None:
        """Give ``car``'s session back (nothing when not held or asked for)."""
        ...


class LocalLiftSessions:
    """Sessions from a lease book of the robot's own (one robot alone in its building).
    ``kind`` names the devices: ``lift`` cars, or ``door`` s lent the same way."""

    def __init__(self, holder: str, book: LeaseBook | None = None, *,
                 kind: str = "lift") -> None:
        self.holder = holder
        self.kind = kind
        self._book = book or LeaseBook(LeaseBookConfig())

    def request(self, car: str, now: float, flow: str | None = None) -> None:
        name = resource(car, self.kind)
        lease = self._book.lease(name, self.holder)
        if lease is None:
            if self._book.position(name, self.holder) is None:
                self._book.request(name, self.holder, now=now, duration=SESSION_LEASE,
                                   flow=flow)
        elif lease.expires_at - now < SESSION_LEASE / 2:
            self._book.renew(name, self.holder, now=now, duration=SESSION_LEASE)

    def granted(self, car: str, now: float) -> bool:
        self._book.tick(now)
        return self._book.lease(resource(car, self.kind), self.holder) is not None

    def rejected(self, car: str) -> bool:
        name = resource(car, self.kind)
        return (self._book.lease(name, self.holder) is None
                and self._book.position(name, self.holder) is None)

    def release(self, car: str, now: float) -> None:
        self._book.release(resource(car, self.kind), self.holder, now=now)
