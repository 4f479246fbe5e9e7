"""Schedules that start stored tasks on the robot's calendar (``runtime.tasks.schedules``)."""

from __future__ import annotations

import logging
from typing import Annotated

from fastapi import APIRouter, Path, Query, Response

from polynav.api.deps import RuntimeDep
from polynav.api.errors import BODY, LOOKUP, STATE, responses
from polynav.api.schemas_tasks import ScheduleIn, ScheduleOut, ScheduleSpecIn

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/schedules", tags=["tasks"], responses=LOOKUP)

ScheduleId = Annotated[str, Path(min_length=1, max_length=200, description="the schedule's id")]


@router.get("", operation_id="list_schedules", response_model=list[ScheduleOut])
def list_schedules(runtime: RuntimeDep, task_id: Annotated[
        str | None, Query(max_length=200, description="only this task's")] = None
                   ) -> list[ScheduleOut]:
    return [ScheduleOut.from_domain(s) for s in runtime.tasks.schedules.list(task_id)]


@router.post("", operation_id="create_schedule", response_model=ScheduleOut, status_code=201,
             responses=responses(BODY, STATE))
def create_schedule(body: ScheduleIn, runtime: RuntimeDep) -> ScheduleOut:
    """Schedule a stored task (404 for an unknown task; 409 for a date-time in the past, a
    date or time that does not exist, an unknown weekday; nothing is made)."""
    return ScheduleOut.from_domain(runtime.tasks.schedules.create(
        body.task_id, body.to_domain(), enabled=body.enabled))


@router.get("/{schedule_id}", operation_id="get_schedule", response_model=ScheduleOut)
def get_schedule(schedule_id: ScheduleId, runtime: RuntimeDep) -> ScheduleOut:
    return ScheduleOut.from_domain(runtime.tasks.schedules.get(schedule_id))


@router.put("/{schedule_id}", operation_id="update_schedule", response_model=ScheduleOut,
            responses=responses(BODY, STATE))
def update_schedule(schedule_id: ScheduleId, body: ScheduleSpecIn, runtime: RuntimeDep
                    ) -> ScheduleOut:
    """Change when it fires (its count of starts begins again) and whether it is on."""
    return ScheduleOut.from_domain(runtime.tasks.schedules.update(
        schedule_id, body.to_domain(), enabled=body.enabled))


@router.delete("/{schedule_id}", operation_id="delete_schedule", status_code=204,
               responses=STATE)
def delete_schedule(schedule_id: ScheduleId, runtime: RuntimeDep) -> Response:
    runtime.tasks.schedules.delete(schedule_id)
    return Response(status_code=204)
