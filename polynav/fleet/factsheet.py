"""A polynav robot's VDA 5050 factsheet (§6.17): what the vehicle is and what it understands.

Built from the robot's profile (speeds, accelerations, footprint) and from what the vehicle
side of polynav carries out (:mod:`polynav.fleet.agent`: the instant actions it knows, no node
or edge actions, the timing of its messages), so a master control plans with the robot's own
numbers. It is a plain JSON object, checked against the official factsheet schema of its
version before it is returned.

What the profile does not say is stated here: a polynav robot carries no load of its own
(``maxLoadMass`` 0, no load sets), drives on a differential base (``DIFF``) that localizes on
the natural scene (``NATURAL``) and navigates freely (``AUTONOMOUS``); its height is not in the
profile, so ``heightMax`` is :data:`DEFAULT_HEIGHT`.
"""

from __future__ import annotations

import math
from typing import Any

from polynav.fleet import messages as m
from polynav.fleet.mqtt_transport import MAX_MESSAGE
from polynav.fleet.order_check import MAX_ID, MAX_NODES
from polynav.fleet.vda5050 import validation
from polynav.robot.profile import RobotProfile

DEFAULT_HEIGHT = 1.2
"""The height [m] given as ``heightMax`` (profiles have no height: the demo robot's)."""

_INSTANT: dict[str, tuple[str, tuple[tuple[str, str, bool], ...]]] = {
    m.ActionType.CANCEL_ORDER.value: ("cancel the running order; the robot stops", ()),
    m.ActionType.START_PAUSE.value: ("stop and hold the order until stopPause", ()),
    m.ActionType.STOP_PAUSE.value: ("go on with the order held by startPause", ()),
    m.ActionType.INIT_POSITION.value: (
        "set the robot's pose on a map (another map restarts navigation there)",
        (("x", "NUMBER", False), ("y", "NUMBER", False), ("theta", "NUMBER", False),
         ("mapId", "STRING", True))),
    m.ActionType.STATE_REQUEST.value: ("publish the state now", ()),
    m.ActionType.FACTSHEET_REQUEST.value: ("publish this factsheet now", ()),
    m.ActionType.START_CHARGING.value: (
        "FINISHED when docked on a charger (an order to a charger point docks there)", ()),
    m.ActionType.STOP_CHARGING.value: (
        "FINISHED when off the charger (any order backs off it first)", ()),
}


def factsheet(profile: RobotProfile, *, serial_number: str, header: m.Header,
              state_period: float, visualization_period: float | None,
              order_period: float) -> dict[str, Any]:
    """The factsheet of robot ``serial_number`` (see the module docstring).

    Args:
        profile: the robot.
        serial_number: its VDA 5050 serial number.
        header: the message's header (its version is the factsheet's).
        state_period: the longest between two states [s].
        visualization_period: between two visualization messages [s], None if none.
        order_period: the shortest time [s] between two orders the vehicle reads (its control
            period: orders are read once a period).

    Raises:
        SchemaViolation: the factsheet breaks its schema (a bug).
    """
    width, length, outline = _outline(profile)
    limits = profile.limits
    timing: dict[str, Any] = {"minOrderInterval": order_period,
                              "minStateInterval": order_period,
                              "defaultStateInterval": state_period}
    if visualization_period is not None:
        timing["visualizationInterval"] = visualization_period
    sheet: dict[str, Any] = {
        "headerId": header.header_id, "timestamp": header.timestamp, "version": header.version,
        "manufacturer": header.manufacturer, "serialNumber": serial_number,
        "typeSpecification": {
            "seriesName": profile.name, "seriesDescription": profile.description or profile.name,
            "agvKinematic": "DIFF", "agvClass": "CARRIER", "maxLoadMass": 0,
            "localizationTypes": ["NATURAL"], "navigationTypes": ["AUTONOMOUS"],
        },
        "physicalParameters": {
            "speedMin": 0.0, "speedMax": limits.max_linear_velocity,
            "accelerationMax": limits.linear_acceleration,
            "decelerationMax": limits.linear_deceleration,
            "heightMax": DEFAULT_HEIGHT, "width": width, "length": length,
        },
        # What the vehicle enforces on what it reads (fleet/mqtt_transport.py, order_check.py).
        "protocolLimits": {"maxStringLens": {"msgLen": MAX_MESSAGE, "idLen": MAX_ID},
                           "maxArrayLens": {"order.nodes": MAX_NODES,
                                            "order.edges": MAX_NODES - 1},
                           "timing": timing},
        "protocolFeatures": {
            "optionalParameters": [
                {"parameter": "order.nodes.nodePosition", "support": "REQUIRED",
                 "description": "a node without a position is rejected"},
                {"parameter": "state.agvPosition", "support": "SUPPORTED"},
                {"parameter": "state.velocity", "support": "SUPPORTED"},
            ],
            "agvActions": [
                # No blockingTypes: 2.1.0's schema puts its enum on the array itself, so no
                # list passes it (a defect of the published schema).
                {"actionType": name, "actionDescription": text, "actionScopes": ["INSTANT"],
                 "actionParameters": [
                     {"key": key, "valueDataType": kind, "isOptional": optional}
                     for key, kind, optional in parameters]}
                for name, (text, parameters) in _INSTANT.items()
            ],
        },
        "agvGeometry": {
            "envelopes2d": [{"set": "base", "polygonPoints": outline,
                             "description": "the robot's footprint"}],
        },
        "loadSpecification": {"loadPositions": [], "loadSets": []},
    }
    validation.validate("factsheet", header.version, sheet)
    return sheet


def _outline(profile: RobotProfile) -> tuple[float, float, list[dict[str, float]]]:
    """Width (across, y) and length (along, x) [m] of the footprint, and its outline."""
    footprint = profile.footprint
    if footprint.radius > 0:
        r = footprint.radius
        points = [(r * math.cos(2 * math.pi * k / 16), r * math.sin(2 * math.pi * k / 16))
                  for k in range(16)]
    else:
        points = [(float(x), float(y)) for x, y in footprint.vertices]
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    outline = [{"x": round(x, 4), "y": round(y, 4)} for x, y in points]
    return round(max(ys) - min(ys), 4), round(max(xs) - min(xs), 4), outline
