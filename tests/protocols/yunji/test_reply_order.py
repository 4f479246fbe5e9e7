"""A command's reply comes before the notifications it causes, on the connection that sent it.

Client code written for the robot sends a command and reads one line expecting the reply (a
single ``recv`` and ``json.loads`` of its first line is common). Each test sends one command that
makes the runtime publish an event at once, reads exactly one line and requires it to be that
command's response; the notification follows. The harness runs runtime commands synchronously
(see conftest), so the event is published while the handler still runs: without the outbox's
hold the pump would deliver it first, every time.
"""

from __future__ import annotations

from typing import Any

import pytest

from tests.protocols.yunji.conftest import Client, Harness


def _first_line_is_the_reply(client: Client, command: str) -> dict[str, Any]:
    client.send(command)
    first = client.read()
    path = command.split("?", 1)[0]
    assert (first["type"], first["command"]) == ("response", path), first
    assert first["status"] == "OK", first
    return first


def _next_notification(client: Client) -> str:
    packet = client.read()
    assert packet["type"] == "notification", packet
    return str(packet["code"])


def _fresh_client_in_a_move(harness: Harness, command: str = "/api/move?marker=kitchen") -> Client:
    """A new connection (no notification of the start left unread) while a move runs."""
    assert harness.client().request(command)["status"] == "OK"
    harness.runtime.advance(1.0)
    return harness.client()


@pytest.mark.parametrize(
    ("command", "code"),
    [
        ("/api/move?marker=lobby", "01001"),
        ("/api/move?location=5.5,12.5,0.0", "01001"),
        ("/api/move?markers=lobby,front_desk&count=1", "01101"),
        ("/api/estop?flag=true", "02003"),
        ("/api/software/restart", "02006"),
        ("/api/shutdown?reboot=true", "02000"),
    ],
)
def test_the_reply_comes_before_the_notification_the_command_causes(
    client: Client, command: str, code: str
) -> None:
    _first_line_is_the_reply(client, command)
    assert _next_notification(client) == code


def test_cancel_is_answered_before_01004(harness: Harness) -> None:
    client = _fresh_client_in_a_move(harness)
    _first_line_is_the_reply(client, "/api/move/cancel")
    assert _next_notification(client) == "01004"


def test_cancelling_a_cruise_is_answered_before_its_notifications(harness: Harness) -> None:
    client = _fresh_client_in_a_move(harness, "/api/move?markers=lobby,kitchen&count=1")
    _first_line_is_the_reply(client, "/api/move/cancel")
    assert {_next_notification(client), _next_notification(client)} == {"01004", "01104"}


def test_releasing_the_estop_is_answered_before_02004(harness: Harness) -> None:
    assert harness.client().request("/api/estop?flag=true")["status"] == "OK"
    client = harness.client()
    _first_line_is_the_reply(client, "/api/estop?flag=false")
    assert _next_notification(client) == "02004"


def test_other_connections_get_the_notification_without_waiting(harness: Harness) -> None:
    sender, watcher = harness.client(), harness.client()
    _first_line_is_the_reply(sender, "/api/move?marker=lobby")
    packet = watcher.read()
    assert (packet["type"], packet["code"]) == ("notification", "01001")
