"""Lift sessions from the site's lease book, asked for in VDA 5050 zone requests.

A robot's lift sequence asks for a car's session (:class:`~polynav.runtime.lift_sessions.
LiftSessions`); in a building this is the implementation its agent puts in. A session is a lease
on the zone ``lift:<car>`` of the master control's lease book: asked for with a ``zoneRequest``
(``ACCESS``, :data:`~polynav.runtime.lift_sessions.SESSION_LEASE` seconds), renewed while held,
given back with ``RELEASE``. The lease book queues robots first come, first served, answers a
waiter ``REJECTED`` after its ``max_wait`` (it then asks again at once, keeping its place) and
lets a lease lapse when its robot stops renewing, so no robot holds a car for ever.
"""

from __future__ import annotations

import itertools
import logging
import math
from dataclasses import dataclass

from polynav.fleet import messages as m
from polynav.fleet.traffic import SendRequest
from polynav.runtime.lift_sessions import SESSION_LEASE, resource

log = logging.getLogger(__name__)

RENEW_BEFORE = 20.0
"""A held session is renewed when less than this [s] is left of its lease."""

REASK_AFTER = 5.0
"""A session asked for and not answered for this long [s] is asked for again (same id): zone
requests travel at QoS 0, and one sent while the fleet manager was off the broker is lost."""


@dataclass(slots=True)
class _Session:
    request_id: str
    flow: str | None = None  # the way through, sent with every ask of this session
    granted: bool = False
    rejected: bool = False
    expiry: float = -math.inf
    renew_sent: float = -math.inf
    heard: float = -math.inf  # when it was last asked for or answered [s]


class FleetLiftSessions:
    """One robot's car sessions through the fleet (see the module docstring).

    Args:
        holder: the robot's id.
        send: publishes a zone request (the agent's).
        kind: the devices: ``lift`` cars, or ``door`` s (leases on ``door:<name>``, asked for
            and renewed the same way).
    """

    def __init__(self, holder: str, send: SendRequest, *, kind: str = "lift") -> None:
        self.holder = holder
        self.kind = kind
        self._send = send
        self._sessions: dict[str, _Session] = {}
        self._ids = itertools.count(1)
        self.rejections = 0
        self._now = -math.inf  # the time of the last request: answers are stamped with it

    def request(self, car: str, now: float, flow: str | None = None) -> None:
        """Ask for ``car`` (called each tick while it is wanted): a new ask, a renewal while
        held, or the same ask again when no answer came within :data:`REASK_AFTER`. ``flow``
        (the way through a door) is the new ask's; renewals and re-asks keep it."""
        self._now = now
        session = self._sessions.get(car)
        if session is None or session.rejected:
            session = _Session(f"{self.holder}-{self.kind}-{next(self._ids)}", flow=flow,
                               heard=now)
            self._sessions[car] = session
            self._ask(car, session)
        elif session.granted and session.expiry - now < RENEW_BEFORE and (
                now - session.renew_sent > 1.0):
            session.renew_sent = now
            self._ask(car, session)
        elif not session.granted and now - session.heard > REASK_AFTER:
            session.heard = now
            self._ask(car, session)

    def resend(self) -> None:
        """Ask again for every session asked for or held (same request ids), after the link to
        the fleet was lost with a request or its answer perhaps in it."""
        for car, session in self._sessions.items():
            if not session.rejected:
                self._ask(car, session)

    def _ask(self, car: str, session: _Session) -> None:
        self._send(session.request_id, resource(car, self.kind), m.ZoneRequestType.ACCESS,
                   SESSION_LEASE, session.flow)

    def granted(self, car: str, now: float) -> bool:
        session = self._sessions.get(car)
        return session is not None and session.granted and session.expiry > now

    def rejected(self, car: str) -> bool:
        session = self._sessions.get(car)
        return session is not None and session.rejected

    def release(self, car: str, now: float) -> None:
        session = self._sessions.pop(car, None)
        if session is not None:
            self._send(session.request_id, resource(car, self.kind), m.ZoneRequestType.RELEASE,
                       0.0)

    def on_response(self, response: m.ZoneResponse) -> None:
        """Take in the fleet's answer (answers about other zones are not ours: ignored)."""
        if not response.zone_id.startswith(f"{self.kind}:"):
            return
        car = response.zone_id.split(":", 1)[1]
        session = self._sessions.get(car)
        if session is None or session.request_id != response.request_id:
            return
        grant = response.grant_type
        session.heard = self._now
        if grant is m.GrantType.GRANTED:
            session.granted = True
            session.expiry = (response.lease_expiry if response.lease_expiry is not None
                              else math.inf)
        elif grant in (m.GrantType.REJECTED, m.GrantType.REVOKED, m.GrantType.EXPIRED):
            log.warning("%s: session of %s %s", self.holder, car, grant.value)
            if grant is m.GrantType.REJECTED:
                self.rejections += 1
            session.granted, session.rejected = False, True
