"""Pydantic models of the door routes (``GET /api/doors``, an operator's hand on a door)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from polynav.robot.door import DoorStatus


class DoorOut(BaseModel):
    """One door or gate as it reports itself."""

    name: str
    kind: Literal["door", "gate"]
    floor: str
    segment: list[float] = Field(description="the leaf's ends [m]: x1, y1, x2, y2 (map frame)")
    width: float = Field(description="clear width of the passage [m]")
    state: Literal["closed", "opening", "open", "closing"]
    holders: list[str] = Field(description="who holds it open: robots' ids, 'operator'")
    answering: bool = Field(description="whether its controller answers requests")

    @classmethod
    def from_domain(cls, status: DoorStatus) -> DoorOut:
        spec = status.spec
        return cls(name=spec.name, kind=spec.kind.value, floor=spec.floor,
                   segment=[spec.x1, spec.y1, spec.x2, spec.y2], width=spec.width,
                   state=status.state.value, holders=list(status.holders),
                   answering=status.answering)


class DoorsOut(BaseModel):
    """GET /api/doors: every door and gate of the building."""

    doors: list[DoorOut]


DoorStateName = Literal["closed", "opening", "open", "closing"]


class DoorNowOut(BaseModel):
    """A door the robot waits at or passes, and its state."""

    name: str
    state: DoorStateName | None = Field(
        description="null when the door is on no floor the status reads (not expected)")


class StatusDoorsOut(BaseModel):
    """The doors in the status (sent at the status' rate, so names and states only; the
    geometry is ``GET /api/doors``)."""

    model_config = ConfigDict(json_schema_extra={"examples": [{
        "waiting_for": {"name": "office_door", "state": "opening"},
        "passing": [{"name": "office_door", "state": "opening"}],
        "floor": {"office_door": "opening", "lab_gate": "closed"},
    }]})

    waiting_for: DoorNowOut | None = Field(
        description="the door the robot stands paused before until it opens")
    passing: list[DoorNowOut] = Field(
        description="the doors the robot holds open to pass now (granted and asked open)")
    floor: dict[str, DoorStateName] = Field(
        description="each door of the robot's floor, name -> state")
