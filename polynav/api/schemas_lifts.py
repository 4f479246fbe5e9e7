"""Pydantic models of the lift routes (``GET /api/lifts``, a car's request and mode)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, StrictBool

from polynav.robot.lift import DoorRequest, LiftMode, LiftRequest, LiftState


class LiftOut(BaseModel):
    """One car as it reports itself (RMF ``LiftState``)."""

    name: str
    floors: list[str] = Field(description="the floors it serves, lowest first")
    current_floor: str = Field(description="where it stands, or the floor it last passed")
    destination_floor: str
    door: Literal["closed", "opening", "open", "closing"]
    motion: Literal["stopped", "up", "down"]
    mode: Literal["normal", "out_of_service"]
    session: str = Field(description="the robot (or operator) holding its session, '' if none")
    riders: int
    capacity: int

    @classmethod
    def from_domain(cls, state: LiftState) -> LiftOut:
        return cls(name=state.name, floors=list(state.floors),
                   current_floor=state.current_floor,
                   destination_floor=state.destination_floor, door=state.door.value,
                   motion=state.motion.value, mode=state.mode.value,
                   session=state.session_id, riders=state.riders, capacity=state.capacity)


class LiftsOut(BaseModel):
    """GET /api/lifts: every car of the building."""

    lifts: list[LiftOut]


class LiftRequestIn(BaseModel):
    """An operator's request to a car: go to ``floor`` with the doors open (or closed), or
    end the operator's session. It takes the car's session as ``session`` (``operator`` by
    default), so robots wait until it is ended."""

    model_config = ConfigDict(extra="forbid")

    session: str = Field(default="operator", min_length=1, max_length=64)
    floor: str | None = Field(default=None, min_length=1, max_length=64)
    door: Literal["open", "closed"] = "open"
    end_session: StrictBool = False  # JSON true/false only, as the document says

    def to_domain(self) -> LiftRequest:
        return LiftRequest(self.session, self.floor or "", DoorRequest(self.door),
                           self.end_session)


class LiftModeIn(BaseModel):
    """Put a (simulated) car in or out of service."""

    model_config = ConfigDict(extra="forbid")

    mode: Literal["normal", "out_of_service"]

    def to_domain(self) -> LiftMode:
        return LiftMode(self.mode)
