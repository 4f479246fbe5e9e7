"""A robot's car and door sessions through the fleet: asked, renewed, asked again."""

from __future__ import annotations

from polynav.fleet import messages as m
from polynav.fleet.lift_sessions import REASK_AFTER, FleetLiftSessions

Sent = list[tuple[str, str, m.ZoneRequestType]]


def _sessions(sent: Sent, kind: str = "lift") -> FleetLiftSessions:
    def send(rid: str, zone: str, request: m.ZoneRequestType, _duration: float,
             _flow: str | None = None) -> None:
        sent.append((rid, zone, request))

    return FleetLiftSessions("r1", send, kind=kind)


def _answer(sessions: FleetLiftSessions, sent: Sent, grant: m.GrantType) -> None:
    rid, zone, _ = sent[-1]
    sessions.on_response(m.ZoneResponse(header_id=1, serial_number="r1", request_id=rid,
                                        zone_id=zone, grant_type=grant, lease_expiry=100.0))


def test_a_session_never_answered_is_asked_again_with_the_same_id() -> None:
    sent: Sent = []
    sessions = _sessions(sent)
    sessions.request("A", 0.0)
    sessions.request("A", REASK_AFTER - 0.1)
    assert sent == [("r1-lift-1", "lift:A", m.ZoneRequestType.ACCESS)]
    sessions.request("A", REASK_AFTER + 0.1)
    assert sent[1] == sent[0]
    _answer(sessions, sent, m.GrantType.QUEUED)  # answered: the clock starts again
    sessions.request("A", 2 * REASK_AFTER)
    assert len(sent) == 2
    _answer(sessions, sent, m.GrantType.GRANTED)
    sessions.request("A", 3 * REASK_AFTER)
    assert len(sent) == 2 and sessions.granted("A", 3 * REASK_AFTER)


def test_door_leases_are_asked_again_as_doors_after_a_lost_link() -> None:
    sent: Sent = []
    doors = _sessions(sent, kind="door")
    doors.request("lobby_gate", 0.0)
    doors.resend()
    assert [z for _, z, _ in sent] == ["door:lobby_gate", "door:lobby_gate"]
    assert sent[1][0] == sent[0][0]


def test_a_door_is_asked_with_the_way_through_and_every_ask_again_keeps_it() -> None:
    flows: list[str | None] = []

    def send(rid: str, zone: str, request: m.ZoneRequestType, _duration: float,
             flow: str | None = None) -> None:
        flows.append(flow)

    doors = FleetLiftSessions("r1", send, kind="door")
    doors.request("fire_door_east", 0.0, "W")
    doors.request("fire_door_east", REASK_AFTER + 0.1, "E")  # the way of the first ask stays
    doors.resend()
    assert flows == ["W", "W", "W"]
