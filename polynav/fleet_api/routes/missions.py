"""``/api/missions``: missions queued, dispatched to robots, followed to their end."""

from __future__ import annotations

from fastapi import APIRouter, Path

from polynav.fleet.records import MissionState
from polynav.fleet_api.deps import ManagerDep
from polynav.fleet_api.errors import errors
from polynav.fleet_api.schemas import MissionAccepted, MissionIn, MissionOut

router = APIRouter(prefix="/api/missions", tags=["missions"])

_ID = Path(min_length=1, max_length=200)


@router.post("", status_code=202, response_model=MissionAccepted, responses=errors({
    400: "the body is not JSON (code `malformed_json`)",
    404: "a stop names a map or point the site does not have (code `not_found`)",
    409: "the mission id is taken by a mission with other stops (code `conflict`)",
    422: "the body does not match this document (code `validation_error`)",
    503: "the fleet's records cannot be reached now (code `records_unavailable`)",
}))
def post_mission(body: MissionIn, manager: ManagerDep) -> MissionAccepted:
    """Queue a mission; it is dispatched to the best robot (free, near, with battery)."""
    mission = manager.submit([stop.model_dump() for stop in body.stops],
                             mission_id=body.mission_id)
    return MissionAccepted(mission_id=mission.mission_id, state=mission.state.value)


@router.get("", response_model=list[MissionOut],
            responses=errors({422: "an unknown state (code `validation_error`)"}))
def list_missions(manager: ManagerDep,
                  state: MissionState | None = None) -> list[MissionOut]:
    """Every mission (or those in ``state``), oldest first."""
    return [MissionOut.from_domain(mission) for mission in manager.missions(state)]


@router.get("/{mission_id}", response_model=MissionOut,
            responses=errors({404: "no such mission (code `not_found`)"}))
def get_mission(manager: ManagerDep, mission_id: str = _ID) -> MissionOut:
    """One mission."""
    return MissionOut.from_domain(manager.mission(mission_id))


@router.delete("/{mission_id}", response_model=MissionOut, responses=errors({
    404: "no such mission (code `not_found`)",
    409: "the mission has already ended (code `conflict`)",
}))
def cancel_mission(manager: ManagerDep, mission_id: str = _ID) -> MissionOut:
    """Cancel a queued or active mission (its robot is told to cancel its order)."""
    return MissionOut.from_domain(manager.cancel(mission_id))
