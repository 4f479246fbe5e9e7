"""The fleet's tables (SQLAlchemy Core), the same on SQLite and PostgreSQL.

Why leases cannot be granted twice, whatever the isolation level: the ``leases`` table holds
only leases not yet given back (released, revoked and expired rows are deleted, their history
is in ``audit``), and each occupies one numbered *slot* of its resource, ``0 <= slot <
capacity``, unique per resource. A capacity-1 resource has the one slot 0, so two leases on it
are two rows with the same (resource, slot): the database refuses the second, even from two
fleet managers that both believed the resource free. The store's transactions (serializable
on PostgreSQL, ``BEGIN IMMEDIATE`` on SQLite) make that case rare; the constraint makes it
impossible.
"""

from __future__ import annotations

from sqlalchemy import (
    JSON,
    CheckConstraint,
    Column,
    Double,
    Index,
    Integer,
    MetaData,
    String,
    Table,
    UniqueConstraint,
    text,
)

metadata = MetaData()

NAME = 200  # longest resource, robot, mission or order name [characters]

missions = Table(
    "fleet_missions",
    metadata,
    # seq orders missions added at the same site time; id is the name the fleet uses.
    Column("seq", Integer, primary_key=True, autoincrement=True),
    Column("id", String(NAME), nullable=False, unique=True),
    Column("state", String(16), nullable=False),
    Column("stops", JSON, nullable=False),
    Column("robot", String(NAME), nullable=True),
    Column("created", Double, nullable=False),
    Column("updated", Double, nullable=False),
    Column("attempts", Integer, nullable=False, default=0),
    CheckConstraint("state IN ('queued', 'active', 'done', 'failed', 'cancelled')",
                    name="mission_state"),
    # Queued: no robot; active or done: one robot. Failed or cancelled: the last robot, if
    # any (a mission cancelled while queued never had one).
    CheckConstraint("(state <> 'queued' OR robot IS NULL) AND "
                    "(state NOT IN ('active', 'done') OR robot IS NOT NULL)",
                    name="mission_robot"),
)
Index("fleet_missions_queue", missions.c.state, missions.c.created, missions.c.seq)
# A robot does one mission at a time: a second claim for it (a retried one, or two fleet
# managers at once) finds the first instead of taking another mission.
Index("fleet_missions_one_active", missions.c.robot, unique=True,
      sqlite_where=text("state = 'active'"), postgresql_where=text("state = 'active'"))

orders = Table(
    "fleet_orders",
    metadata,
    Column("order_id", String(NAME), primary_key=True),
    Column("update_id", Integer, primary_key=True),
    Column("robot", String(NAME), nullable=False),
    Column("mission", String(NAME), nullable=True),
    Column("state", String(16), nullable=False),
    Column("sent_at", Double, nullable=False),
    Column("confirmed_at", Double, nullable=True),
    Column("sends", Integer, nullable=False, default=1),
    CheckConstraint("state IN ('sent', 'confirmed', 'superseded')", name="order_state"),
    CheckConstraint("update_id >= 0", name="order_update_id"),
)
Index("fleet_orders_unconfirmed", orders.c.state, orders.c.sent_at)

leases = Table(
    "fleet_leases",
    metadata,
    Column("lease_id", Integer, primary_key=True, autoincrement=True),
    Column("resource", String(NAME), nullable=False),
    Column("slot", Integer, nullable=False),
    Column("capacity", Integer, nullable=False),
    Column("holder", String(NAME), nullable=False),
    Column("granted_at", Double, nullable=False),
    Column("expires_at", Double, nullable=False),
    UniqueConstraint("resource", "slot", name="lease_one_per_slot"),
    UniqueConstraint("resource", "holder", name="lease_one_per_holder"),
    CheckConstraint("slot >= 0 AND slot < capacity", name="lease_slot_in_capacity"),
    CheckConstraint("expires_at > granted_at", name="lease_expires_after_grant"),
    # A lease id is never given again (the audit trail tells each lease's life by its id);
    # SQLite reuses the largest rowid after a delete unless told not to.
    sqlite_autoincrement=True,
)
Index("fleet_leases_holder", leases.c.holder)
Index("fleet_leases_expiry", leases.c.expires_at)

audit = Table(
    "fleet_audit",
    metadata,
    Column("id", Integer, primary_key=True, autoincrement=True),
    Column("at", Double, nullable=False),
    Column("actor", String(NAME), nullable=False),
    Column("what", String(64), nullable=False),
    Column("detail", JSON, nullable=False),
    sqlite_autoincrement=True,
)
