"""``polynav users``: the native API's users in a site's data directory.

A module of its own outside :mod:`polynav.api`, so that ``polynav --help`` does not import the
web stack; the store and the hasher are imported when a ``users`` command runs.

Passwords are read from a prompt (twice, not echoed) or, for scripts, as one line of standard
input (``--password-stdin``); never from the command line, where ``ps`` and the shell history
would show them. They reach the store only as argon2 hashes.
"""

from __future__ import annotations

import argparse
import getpass
import sys
from pathlib import Path

EXIT_BAD_INPUT = 2
#: As :data:`polynav.store.user_tables.ROLES` (a test checks they agree).
ROLES = ("viewer", "operator")


def add_parser(subparsers: argparse._SubParsersAction, default_data: Path) -> None:  # type: ignore[type-arg]
    """Add ``users add|rm|passwd|list`` to the command line's sub-commands."""
    parser = subparsers.add_parser(
        "users", help="add, remove or list the native API's users",
        description="Manage who may log in to the native API when it listens beyond loopback "
        "(polynav run --host ...): viewers read, operators also drive and edit.")
    sub = parser.add_subparsers(dest="users_command", required=True)

    def data(one: argparse.ArgumentParser) -> argparse.ArgumentParser:
        one.add_argument("--data", type=Path, default=default_data,
                         help="site data directory (default: %(default)s)")
        return one

    add = data(sub.add_parser("add", help="add a user", description="Add a user; the "
                              "password is asked for (or read from stdin)."))
    add.add_argument("name")
    add.add_argument("--role", choices=ROLES, default="viewer",
                     help="viewer reads, operator also drives and edits (default: %(default)s)")
    add.add_argument("--password-stdin", action="store_true",
                     help="read the password as one line of standard input")
    rm = data(sub.add_parser("rm", help="remove a user", description="Remove a user; its "
                             "logins end at once, on a running server too."))
    rm.add_argument("name")
    passwd = data(sub.add_parser("passwd", help="change a user's password",
                                 description="Change a user's password; its logins end."))
    passwd.add_argument("name")
    passwd.add_argument("--password-stdin", action="store_true",
                        help="read the password as one line of standard input")
    data(sub.add_parser("list", help="list the users", description="List the users (name, "
                        "role, created)."))


def _read_password(from_stdin: bool) -> str:
    """The new password: one line of stdin, or typed twice at a prompt.

    Raises:
        ValueError: the two typed passwords differ.
    """
    if from_stdin:
        return sys.stdin.readline().rstrip("\r\n")
    first = getpass.getpass("password: ")
    if getpass.getpass("again: ") != first:
        raise ValueError("the two passwords differ")
    return first


def main(args: argparse.Namespace) -> int:
    """Run the ``users`` sub-command in ``args``; PolynavErrors propagate to the caller."""
    from polynav.api.auth import now_iso
    from polynav.api.auth_passwords import hash_password
    from polynav.store.site_store import SiteStore

    store = SiteStore.open(args.data)  # never seeded: users need no site
    try:
        if args.users_command == "list":
            for user in store.users():
                print(f"{user.name}\t{user.role}\t{user.created}")
            return 0
        if args.users_command == "rm":
            store.remove_user(args.name)
            print(f"removed user {args.name!r}")
            return 0
        if args.users_command == "add":
            store.user_count()  # the store is readable before a password is typed
        try:
            hashed = hash_password(_read_password(args.password_stdin))
        except ValueError as exc:
            print(f"polynav users {args.users_command}: {exc}", file=sys.stderr)
            return EXIT_BAD_INPUT
        if args.users_command == "add":
            store.add_user(args.name, args.role, hashed, now_iso())
            print(f"added user {args.name!r} ({args.role})")
        else:
            store.set_password(args.name, hashed)
            print(f"changed the password of {args.name!r}; its logins ended")
        return 0
    finally:
        store.close()

