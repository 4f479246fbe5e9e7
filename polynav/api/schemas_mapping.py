"""Pydantic models of the mapping session in the status and of its save jobs."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field

from polynav.runtime.mapping_jobs import MappingJob


class MappingJobOut(BaseModel):
    """A save of the map being built (``POST /api/mapping/stop`` or ``/save``), done off the
    robot's control loop; times on the robot's clock [s] as the status ``stamp``."""

    id: str
    name: str = Field(description="the map's name it saves under")
    kind: Literal["stop", "save"] = Field(
        description="`stop`: finish the map, save it, end mapping (the robot is `busy` "
        "meanwhile, then `free`; `mapping` again if the save failed); `save`: save the map so "
        "far, mapping goes on"
    )
    state: Literal["saving", "saved", "failed"] = Field(
        description="`saved`: the map is in `GET /api/maps`"
    )
    error: str | None = Field(description="why it failed (the disk, the store), else null")
    started_at: float
    finished_at: float | None = Field(description="null while saving")

    @classmethod
    def from_domain(cls, job: MappingJob) -> MappingJobOut:
        return cls(id=job.id, name=job.name, kind=job.kind.value,
                   state=job.state.value, error=job.error,
                   started_at=job.started_at, finished_at=job.finished_at)


class MappingStatusOut(BaseModel):
    """The mapping session, in ``GET /api/status`` while mapping or while a stop job saves."""

    kind: Literal["new", "update"] = Field(description="a new map, or extending a saved one")
    map: str | None = Field(description="the saved map being updated (null for a new map)")
    exploration: Literal["off", "exploring", "returning", "done"] = Field(
        description="`off`: driven by hand; `returning`: no frontier left, driving back to "
        "where exploring began"
    )
    frontiers_left: int | None = Field(
        description="frontier clusters the exploration's last search found worth a visit "
        "(null before its first search)"
    )
    targets_reached: int = Field(description="frontiers the exploration reached")
    mapped_area_m2: float = Field(
        description="known (free or occupied) cells x their area [m²], counted about once a "
        "second of the robot's clock"
    )
    scans: int = Field(description="scans the SLAM took")
    started_at: float = Field(description="when mapping started, on the status `stamp`'s clock")
    job: MappingJobOut | None = Field(description="the session's current or last save job")
