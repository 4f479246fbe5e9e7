"""The site database's schema: a version number and the ordered migrations that reach it.

The database records the number of migrations applied in ``schema_version`` (one row). Opening
a store applies the missing ones in order, each in its own transaction together with the new
version number, so a crash during a migration leaves the database at the previous version, never
half-migrated. A database written by a newer polynav (a version above :data:`SCHEMA_VERSION`) is
refused rather than guessed at. Never edit a released migration: append a new one.
"""

from __future__ import annotations

import logging
import sqlite3
from collections.abc import Sequence
from dataclasses import dataclass

from polynav.errors import StorageError

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class Migration:
    """One step of the schema.

    Attributes:
        version: the schema version after this step (1 for the first).
        description: what the step does, for the log.
        statements: SQL statements run in order inside one transaction.
    """

    version: int
    description: str
    statements: tuple[str, ...]


MIGRATIONS: tuple[Migration, ...] = (
    Migration(
        1,
        "floors, maps, points, keepouts, routes, connections, settings",
        (
            # Store-internal counters and flags (the map file serial, "seeded").
            "CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL)",
            "INSERT INTO meta (key, value) VALUES ('map_file_serial', '0')",
            # A floor names its map; no foreign key, as the map rows name their floor.
            "CREATE TABLE floors ("
            " name TEXT PRIMARY KEY,"
            " level INTEGER NOT NULL,"
            " map_name TEXT NOT NULL)",
            # file: the YAML in maps/, written before the row and never rewritten in place.
            "CREATE TABLE maps ("
            " name TEXT PRIMARY KEY,"
            " floor TEXT REFERENCES floors(name) ON DELETE SET NULL ON UPDATE CASCADE,"
            " resolution REAL NOT NULL,"
            " width INTEGER NOT NULL,"
            " height INTEGER NOT NULL,"
            " origin_x REAL NOT NULL,"
            " origin_y REAL NOT NULL,"
            " origin_theta REAL NOT NULL,"
            " file TEXT NOT NULL UNIQUE)",
            "CREATE TABLE points ("
            " map_name TEXT NOT NULL REFERENCES maps(name) ON DELETE CASCADE ON UPDATE CASCADE,"
            " name TEXT NOT NULL,"
            " x REAL NOT NULL,"
            " y REAL NOT NULL,"
            " theta REAL NOT NULL,"
            " kind TEXT NOT NULL,"
            " number INTEGER,"
            " PRIMARY KEY (map_name, name))",
            "CREATE INDEX points_by_name ON points (name)",
            # type: virtual_wall / forbidden_zone / circle_zone; geometry: JSON.
            "CREATE TABLE keepouts ("
            " id INTEGER PRIMARY KEY,"
            " map_name TEXT NOT NULL REFERENCES maps(name) ON DELETE CASCADE ON UPDATE CASCADE,"
            " type TEXT NOT NULL,"
            " geometry TEXT NOT NULL)",
            "CREATE INDEX keepouts_by_map ON keepouts (map_name)",
            "CREATE TABLE routes ("
            " map_name TEXT NOT NULL REFERENCES maps(name) ON DELETE CASCADE ON UPDATE CASCADE,"
            " name TEXT NOT NULL,"
            " geometry TEXT NOT NULL,"
            " PRIMARY KEY (map_name, name))",
            "CREATE TABLE connections (name TEXT PRIMARY KEY, data TEXT NOT NULL)",
            # value: JSON.
            "CREATE TABLE settings (key TEXT PRIMARY KEY, value TEXT NOT NULL)",
        ),
    ),
    Migration(
        2,
        "points: the site's own type number of custom points",
        ("ALTER TABLE points ADD COLUMN custom_type INTEGER",),
    ),
    Migration(
        3,
        "tasks, their schedules, automation tasks",
        (
            # spec: the tree's JSON form as given (polynav.tasks.tree), rebuilt on start-up;
            # blackboard: JSON; state: the root's last state (WAITTING ... FAIL); updated: ISO
            # date-time on the robot's calendar.
            "CREATE TABLE tasks ("
            " id TEXT PRIMARY KEY,"
            " name TEXT NOT NULL,"
            " owner TEXT NOT NULL,"
            " kind TEXT NOT NULL,"
            " spec TEXT NOT NULL,"
            " blackboard TEXT NOT NULL,"
            " state TEXT NOT NULL,"
            " note TEXT NOT NULL,"
            " updated TEXT NOT NULL)",
            # spec: the schedule's JSON (mode, at, times, weekdays, days, loop); next_fire: ISO
            # date-time of the next due start, NULL once it has none; a schedule goes with its
            # task.
            "CREATE TABLE schedules ("
            " id TEXT PRIMARY KEY,"
            " task_id TEXT NOT NULL REFERENCES tasks(id) ON DELETE CASCADE,"
            " spec TEXT NOT NULL,"
            " enabled INTEGER NOT NULL,"
            " starts INTEGER NOT NULL,"
            " next_fire TEXT,"
            " updated TEXT NOT NULL)",
            "CREATE INDEX schedules_by_task ON schedules (task_id)",
            # Galileo's blockly_task: a Python program and the Blockly XML it was made from.
            "CREATE TABLE automations ("
            " id TEXT PRIMARY KEY,"
            " title TEXT NOT NULL,"
            " description TEXT NOT NULL,"
            " py TEXT NOT NULL,"
            " blocklyxml TEXT NOT NULL,"
            " is_enabled INTEGER NOT NULL,"
            " api_key TEXT,"
            " created REAL NOT NULL)",
        ),
    ),
    Migration(
        4,
        "users of the native API and their login tokens",
        (
            # password_hash: an argon2 string (never a password); role: viewer | operator;
            # created: ISO date-time.
            "CREATE TABLE users ("
            " name TEXT PRIMARY KEY,"
            " role TEXT NOT NULL CHECK (role IN ('viewer', 'operator')),"
            " password_hash TEXT NOT NULL,"
            " created TEXT NOT NULL)",
            # token_hash: SHA-256 (hex) of the token handed out; created, expires: seconds
            # since the epoch.
            "CREATE TABLE tokens ("
            " token_hash TEXT PRIMARY KEY,"
            " user_name TEXT NOT NULL REFERENCES users(name) ON DELETE CASCADE"
            " ON UPDATE CASCADE,"
            " created REAL NOT NULL,"
            " expires REAL NOT NULL)",
            "CREATE INDEX tokens_by_user ON tokens (user_name)",
        ),
    ),
)

SCHEMA_VERSION = MIGRATIONS[-1].version


def schema_version(conn: sqlite3.Connection) -> int:
    """The version recorded in the database; 0 for a database without the version table."""
    found = conn.execute(
        "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = 'schema_version'"
    ).fetchone()
    if found is None:
        return 0
    row = conn.execute("SELECT version FROM schema_version").fetchone()
    return 0 if row is None else int(row[0])


def migrate(conn: sqlite3.Connection, migrations: Sequence[Migration] = MIGRATIONS) -> int:
    """Bring the database up to the last of ``migrations``.

    Args:
        conn: a connection in autocommit mode (``isolation_level=None``), outside a transaction.
        migrations: the ordered steps, versions 1, 2, 3, ... (tests pass their own).

    Returns:
        The version the database is at afterwards.

    Raises:
        StorageError: the versions are not consecutive, the database is newer than the last
            migration, or a step fails (that step is rolled back; earlier ones stay).
    """
    for index, step in enumerate(migrations, start=1):
        if step.version != index:
            raise StorageError(f"migration {index} is numbered {step.version}")
    target = len(migrations)
    while True:
        try:
            # IMMEDIATE takes the write lock first, so two processes never run the same step.
            conn.execute("BEGIN IMMEDIATE")
        except sqlite3.Error as exc:
            raise StorageError(f"cannot start a schema migration: {exc}") from exc
        try:
            current = schema_version(conn)
            if current > target:
                raise StorageError(
                    f"the site database has schema version {current}, newer than this "
                    f"polynav knows ({target}); upgrade polynav"
                )
            if current == target:
                conn.execute("COMMIT")
                return current
            step = migrations[current]
            log.info("site database: migration %d (%s)", step.version, step.description)
            if current == 0:
                conn.execute("CREATE TABLE schema_version (version INTEGER NOT NULL)")
                conn.execute("INSERT INTO schema_version (version) VALUES (0)")
            for statement in step.statements:
                conn.execute(statement)
            conn.execute("UPDATE schema_version SET version = ?", (step.version,))
            conn.execute("COMMIT")
        except BaseException as exc:
            conn.execute("ROLLBACK")
            if isinstance(exc, sqlite3.Error):
                raise StorageError(f"schema migration failed: {exc}") from exc
            raise
