"""Rows of the fleet records' tables as the values the records hand out."""

from __future__ import annotations

from typing import Any

from sqlalchemy import Row

from polynav.fleet.records.values import Mission, MissionState, Order, OrderState
from polynav.leases.book import Lease


def mission_of(row: Row[Any]) -> Mission:
    return Mission(mission_id=row.id, state=MissionState(row.state),
                   stops=tuple(row.stops), robot=row.robot, created=row.created,
                   updated=row.updated, attempts=row.attempts)


def order_of(row: Row[Any]) -> Order:
    return Order(order_id=row.order_id, update_id=row.update_id, robot=row.robot,
                 mission=row.mission, state=OrderState(row.state), sent_at=row.sent_at,
                 confirmed_at=row.confirmed_at, sends=row.sends)


def lease_of(row: Row[Any]) -> Lease:
    return Lease(lease_id=row.lease_id, resource=row.resource, holder=row.holder,
                 granted_at=row.granted_at, expires_at=row.expires_at)
