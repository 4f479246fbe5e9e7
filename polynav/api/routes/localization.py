"""POST /api/localization/relocalize: find the robot on its map from the scan alone."""

from __future__ import annotations

import logging

from fastapi import APIRouter

from polynav.api.deps import RuntimeDep
from polynav.api.errors import STATE
from polynav.api.schemas import RelocalizedOut

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/localization", tags=["navigation"], responses=STATE)


@router.post("/relocalize", operation_id="relocalize", response_model=RelocalizedOut)
def relocalize(runtime: RuntimeDep) -> RelocalizedOut:
    """Search the whole current map for the robot's latest scan, with no prior, and restart
    localization at the pose found (it also runs by itself while localization is lost). 409
    ``not_localized`` when the scan matches nowhere well enough, or several places alike (a
    featureless hall, identical rooms); 409 ``conflict`` unless navigating."""
    result = runtime.relocalize()
    assert result.pose is not None
    return RelocalizedOut(x=result.pose.x, y=result.pose.y, theta=result.pose.theta,
                          score=result.score)
