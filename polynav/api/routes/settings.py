"""GET/PUT /api/settings: the robot's tunable settings, range-checked by the runtime."""

from __future__ import annotations

import dataclasses
import enum
import logging
from typing import Any

from fastapi import APIRouter, Body

from polynav.api.deps import RuntimeDep
from polynav.api.errors import BODY, STATE, responses
from polynav.api.schemas import SettingsIn, SettingsOut

log = logging.getLogger(__name__)

router = APIRouter(prefix="/api/settings", tags=["settings"])

SettingsBody = Body(
    description="settings to change, e.g. {\"max_linear_velocity\": 0.5}",
    examples=[{"max_linear_velocity": 0.5}],
)


def _to_json(settings: Any) -> dict[str, Any]:
    """RobotSettings as JSON (its ``to_dict``, or its fields)."""
    if hasattr(settings, "to_dict"):
        return dict(settings.to_dict())
    values = dataclasses.asdict(settings)
    return {k: (v.value if isinstance(v, enum.Enum) else v) for k, v in values.items()}


@router.get("", operation_id="get_settings", response_model=SettingsOut)
def get_settings(runtime: RuntimeDep) -> dict[str, Any]:
    """Every setting with its current value (SI units)."""
    return _to_json(runtime.settings())


@router.put(
    "",
    operation_id="update_settings",
    response_model=SettingsOut,
    responses=responses(BODY, STATE),
)
def update_settings(runtime: RuntimeDep, changes: SettingsIn = SettingsBody) -> dict[str, Any]:
    """Change some settings; all or none apply. 422 for an unknown key, a wrong type or a value
    out of range (the schema says each range); 409 (code `beyond_profile`) for a speed above the
    robot profile's limits or a robot_radius below its body (GET /api/robot shows both: the
    profile in use refuses what the schema allows), and for values that contradict the settings
    they are combined with. Answers with every setting."""
    return _to_json(runtime.update_settings(dict(changes)))
