"""Failures of the fleet layer: leases refused or lost, messages that cannot be delivered."""

from __future__ import annotations

from polynav.errors import Conflict


class LeaseError(Conflict):
    """A lease operation is valid in form but not in the lease book's current state."""

    def __init__(self, resource: str, holder: str, reason: str) -> None:
        super().__init__(f"lease on {resource!r} for {holder!r}: {reason}")
        self.resource = resource
        self.holder = holder
        self.reason = reason


class LeaseNotHeld(LeaseError):
    """The holder has no live lease on the resource: never granted, released or expired.

    A robot that gets this while renewing has lost the resource and must stop using it (leave the
    corridor, do not board the car) before asking again.
    """


class LeaseRefused(LeaseError):
    """The renewal is refused: the holder has kept the resource for its longest hold while others
    wait, so it must release it and queue again behind them."""
