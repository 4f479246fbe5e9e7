"""The fleet manager's records (missions, orders, leases, audit) in SQLite or PostgreSQL.

One data layer on SQLAlchemy Core (:mod:`~polynav.fleet.records.schema`,
:mod:`~polynav.fleet.records.database`, :mod:`~polynav.fleet.records.store`): SQLite by default,
PostgreSQL when the fleet is given ``--db postgresql://...``, where several fleet managers share
one set of records and the database, not any process's memory, keeps a lease from being granted
twice.
"""

from polynav.fleet.records.database import RecordsConfig
from polynav.fleet.records.errors import FleetRecordsError, redacted
from polynav.fleet.records.store import FleetRecords
from polynav.fleet.records.values import AuditEntry, Mission, MissionState, Order, OrderState

__all__ = [
    "AuditEntry",
    "FleetRecords",
    "FleetRecordsError",
    "Mission",
    "MissionState",
    "Order",
    "OrderState",
    "RecordsConfig",
    "redacted",
]
