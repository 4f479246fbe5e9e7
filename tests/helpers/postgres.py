"""A real PostgreSQL server for the tests: ``initdb`` into a temporary directory, ``postgres``
on a free 127.0.0.1 port, stopped and removed at the end.

Debian's PostgreSQL (``make test`` installs it: tools/system_deps.sh) puts its programs in
``/usr/lib/postgresql/<version>/bin``; ``initdb`` is also looked up on PATH.

As root (this machine and CI run the tests as root), ``initdb`` and ``postgres`` refuse to run:
a server must not run with the superuser's rights. Then both are started as an unprivileged
user, ``postgres`` (created by Debian's package) or else ``nobody``, through ``subprocess``'s
``user=``/``group=`` (the same setuid that ``runuser -u`` does, without a PAM session or a
shell in between, so the child is the server itself and stopping it is one signal). Its
directory is made by :func:`tempfile.mkdtemp` under /tmp and given to that user, since
pytest's own temporary directories are private to root. As anyone else, both run as the
current user.

The server trusts connections from 127.0.0.1 (``--auth=trust``, superuser ``polynav``), keeps
its socket in its own directory (``-k``), and runs without fsync: it holds test data only.
"""

from __future__ import annotations

import contextlib
import glob
import os
import pwd
import shutil
import signal
import socket
import subprocess
import tempfile
import time
import uuid
from collections.abc import Iterator
from pathlib import Path

import psycopg
import pytest

SUPERUSER = "polynav"
START_WAIT = 15.0  # seconds for a server to accept connections


def _bin_dir() -> Path:
    """The directory of PostgreSQL's programs (initdb, postgres, pg_isready)."""
    found = shutil.which("initdb")
    if found is not None:
        real = Path(found).resolve()
        if (real.parent / "postgres").exists():
            return real.parent
    versions = sorted(glob.glob("/usr/lib/postgresql/*/bin/initdb"),
                      key=lambda p: int(Path(p).parent.parent.name))
    if not versions:
        pytest.fail("PostgreSQL is not installed (initdb not found): run tools/system_deps.sh "
                    "or apt-get install postgresql")
    return Path(versions[-1]).parent


def _server_user() -> pwd.struct_passwd | None:
    """The user to run the server as when we are root; None when we are not root."""
    if os.geteuid() != 0:
        return None
    for name in ("postgres", "nobody"):
        with contextlib.suppress(KeyError):
            return pwd.getpwnam(name)
    pytest.fail("running as root, and no 'postgres' or 'nobody' user to run PostgreSQL as")


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


class PostgresServer:
    """One PostgreSQL cluster in a temporary directory; :meth:`start` and :meth:`stop` may be
    called again (a test of a lost connection stops it and starts it on the same port)."""

    def __init__(self) -> None:
        self.bin = _bin_dir()
        self.user = _server_user()
        self.base = Path(tempfile.mkdtemp(prefix="polynav-pg-"))
        if self.user is not None:
            os.chown(self.base, self.user.pw_uid, self.user.pw_gid)
        self.data = self.base / "data"
        self.log_path = self.base / "server.log"
        self.port = 0
        self._proc: subprocess.Popen[bytes] | None = None
        self._run([str(self.bin / "initdb"), "-D", str(self.data), "-U", SUPERUSER,
                   "--auth=trust", "--no-sync", "--locale=C", "--encoding=UTF8"])

    def url(self, database: str = "postgres", password: str | None = None) -> str:
        """The URL of ``database`` on this server (a password is accepted and ignored)."""
        secret = f":{password}" if password else ""
        return f"postgresql://{SUPERUSER}{secret}@127.0.0.1:{self.port}/{database}"

    @property
    def pid(self) -> int | None:
        """The server process's id while it runs."""
        return None if self._proc is None else self._proc.pid

    def start(self, port: int | None = None) -> None:
        """Start the server on ``port`` (a free one if None) and wait until it answers.

        Raises:
            RuntimeError: it did not come up (its log is in the message).
        """
        for _ in range(3):  # a free port can be taken by someone else before we bind it
            self.port = port or _free_port()
            with open(self.log_path, "ab") as log_file:
                self._proc = subprocess.Popen(
                    [str(self.bin / "postgres"), "-D", str(self.data), "-p", str(self.port),
                     "-k", str(self.base), "-c", "listen_addresses=127.0.0.1",
                     "-c", "fsync=off", "-c", "synchronous_commit=off",
                     "-c", "full_page_writes=off", "-c", "max_connections=60"],
                    stdin=subprocess.DEVNULL, stdout=log_file, stderr=log_file,
                    **self._as_user())
            if self._wait_ready():
                return
            self.stop()
            if port is not None:
                break
        raise RuntimeError(f"PostgreSQL did not start: {self.log_path.read_text()[-2000:]}")

    def stop(self) -> None:
        """Stop the server (fast shutdown: open connections are closed)."""
        proc, self._proc = self._proc, None
        if proc is None or proc.poll() is not None:
            return
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(timeout=10.0)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(timeout=10.0)

    def remove(self) -> None:
        self.stop()
        shutil.rmtree(self.base, ignore_errors=True)

    def create_database(self) -> str:
        """A new empty database; returns its name."""
        name = f"t_{uuid.uuid4().hex[:12]}"
        with psycopg.connect(self.url(), autocommit=True) as conn:
            conn.execute(f'CREATE DATABASE "{name}"')
        return name

    def empty_database(self, name: str) -> None:
        """Drop everything in database ``name`` (its public schema), as new but faster than
        CREATE DATABASE (half a second each)."""
        with psycopg.connect(self.url(name), autocommit=True) as conn:
            conn.execute("DROP SCHEMA public CASCADE")
            conn.execute("CREATE SCHEMA public")

    def drop_database(self, name: str) -> None:
        with psycopg.connect(self.url(), autocommit=True) as conn:
            conn.execute(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)')

    def _wait_ready(self) -> bool:
        deadline = time.monotonic() + START_WAIT
        while time.monotonic() < deadline:
            if self._proc is None or self._proc.poll() is not None:
                return False
            ready = subprocess.run(
                [str(self.bin / "pg_isready"), "-q", "-h", "127.0.0.1", "-p", str(self.port),
                 "-U", SUPERUSER, "-d", "postgres", "-t", "1"], check=False)
            if ready.returncode == 0:
                return True
            time.sleep(0.05)
        return False

    def _run(self, argv: list[str]) -> None:
        done = subprocess.run(argv, capture_output=True, text=True, check=False,
                              **self._as_user())
        if done.returncode != 0:
            raise RuntimeError(f"{argv[0]} failed: {done.stderr.strip()}")

    def _as_user(self) -> dict[str, object]:
        if self.user is None:
            return {}
        return {"user": self.user.pw_uid, "group": self.user.pw_gid, "extra_groups": []}


@contextlib.contextmanager
def running_postgres() -> Iterator[PostgresServer]:
    """A started server, stopped and removed on exit."""
    server = PostgresServer()
    try:
        server.start()
        yield server
    finally:
        server.remove()


@pytest.fixture(scope="session")
def postgres_server() -> Iterator[PostgresServer]:
    """One server for the session (each xdist worker has its own)."""
    with running_postgres() as server:
        yield server


@pytest.fixture(scope="session")
def postgres_database(postgres_server: PostgresServer) -> str:
    """A database of the session's server for tests, emptied by :func:`postgres_url`."""
    return postgres_server.create_database()


@pytest.fixture
def postgres_url(postgres_server: PostgresServer, postgres_database: str) -> str:
    """The URL of an empty database on the session's server (emptied before each test: the
    tests of one process run one after the other)."""
    postgres_server.empty_database(postgres_database)
    return postgres_server.url(postgres_database)
