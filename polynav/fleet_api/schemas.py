"""The fleet API's bodies (pydantic at the edge; the manager's values become these at once)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from polynav.fleet import messages as m
from polynav.fleet.manager import FleetEvent, RobotView
from polynav.fleet.records import AuditEntry, Mission
from polynav.leases.book import Lease

_NAME = r"^[A-Za-z0-9_.:-]+$"


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)


class StopIn(_Strict):
    """One stop: a site point on a map."""

    point: str = Field(min_length=1, max_length=200)
    map: str = Field(min_length=1, max_length=200)


class MissionIn(_Strict):
    """A mission: stops driven through in order, on any floors."""

    stops: list[StopIn] = Field(min_length=1, max_length=50)
    mission_id: str | None = Field(default=None, min_length=1, max_length=100, pattern=_NAME)


class MissionOut(BaseModel):
    mission_id: str
    state: str
    stops: list[dict[str, Any]]
    robot: str | None
    created: float
    updated: float
    attempts: int

    @classmethod
    def from_domain(cls, mission: Mission) -> MissionOut:
        return cls(mission_id=mission.mission_id, state=mission.state.value,
                   stops=[dict(s) for s in mission.stops], robot=mission.robot,
                   created=mission.created, updated=mission.updated, attempts=mission.attempts)


class MissionAccepted(BaseModel):
    mission_id: str
    state: str


class RobotError(BaseModel):
    type: str
    level: str
    description: str


class RobotOut(BaseModel):
    """A robot's live state as the manager last read it (VDA 5050 terms, SI units)."""

    serial: str
    connection: str
    mission: str | None
    order_id: str | None
    state_at: float | None = Field(description="site time the last state was read [s]")
    map: str | None
    x: float | None
    y: float | None
    theta: float | None
    battery_percent: float | None
    charging: bool | None
    driving: bool | None
    paused: bool | None
    operating_mode: str | None
    current_order: str | None = Field(description="the order the robot's state names")
    nodes_left: int | None
    navigation_state: str | None
    errors: list[RobotError]

    @classmethod
    def from_domain(cls, view: RobotView) -> RobotOut:
        state = view.state
        where = state.agv_position if state is not None else None
        return cls(
            serial=view.serial, connection=view.connection, mission=view.mission,
            order_id=view.order_id, state_at=view.state_at,
            map=where.map_id if where else None, x=where.x if where else None,
            y=where.y if where else None, theta=where.theta if where else None,
            battery_percent=state.battery_state.battery_charge if state else None,
            charging=state.battery_state.charging if state else None,
            driving=state.driving if state else None, paused=state.paused if state else None,
            operating_mode=state.operating_mode if state else None,
            current_order=state.order_id if state else None,
            nodes_left=len(state.node_states) if state else None,
            navigation_state=state.navigation_state if state else None,
            errors=[_error(e) for e in state.errors] if state else [])


def _error(entry: m.ErrorEntry) -> RobotError:
    return RobotError(type=entry.error_type, level=entry.error_level,
                      description=entry.error_description)


class LeaseOut(BaseModel):
    lease_id: int
    resource: str
    holder: str
    granted_at: float
    expires_at: float

    @classmethod
    def from_domain(cls, lease: Lease) -> LeaseOut:
        return cls(lease_id=lease.lease_id, resource=lease.resource, holder=lease.holder,
                   granted_at=lease.granted_at, expires_at=lease.expires_at)


class AuditOut(BaseModel):
    entry_id: int
    at: float
    actor: str
    what: str
    detail: dict[str, Any]

    @classmethod
    def from_domain(cls, entry: AuditEntry) -> AuditOut:
        return cls(entry_id=entry.entry_id, at=entry.at, actor=entry.actor, what=entry.what,
                   detail=dict(entry.detail))


def event_json(event: FleetEvent) -> dict[str, Any]:
    """A fleet event as the WebSocket sends it."""
    detail: Mapping[str, Any] = event.detail
    return {"type": "event", "seq": event.seq, "at": event.at, "kind": event.kind,
            "detail": dict(detail)}
