"""VDA 5050's official schemas ship with polynav and validate messages, naming the bad field."""

from __future__ import annotations

import copy
import importlib.resources
import json
from typing import Any

import jsonschema
import pytest

from polynav.errors import InvalidRequest
from polynav.fleet.vda5050 import validation
from polynav.fleet.vda5050.validation import SchemaViolation


def header(version: str) -> dict[str, Any]:
    return {"headerId": 7, "timestamp": "2026-11-28T11:40:03.12Z", "version": version,
            "manufacturer": "polynav", "serialNumber": "robot1"}


def connection(version: str) -> dict[str, Any]:
    return {**header(version), "connectionState": "ONLINE"}


def order(version: str) -> dict[str, Any]:
    return {
        **header(version), "orderId": "robot1-1", "orderUpdateId": 0,
        "nodes": [
            {"nodeId": "office_1", "sequenceId": 0, "released": True, "actions": [],
             "nodePosition": {"x": 14.3, "y": 20.5, "theta": 1.57, "mapId": "floor1"}},
            {"nodeId": "room_201", "sequenceId": 2, "released": True, "actions": [
                {"actionId": "a1", "actionType": "pick", "blockingType": "HARD"}]},
        ],
        "edges": [{"edgeId": "e1", "sequenceId": 1, "released": True,
                   "startNodeId": "office_1", "endNodeId": "room_201", "actions": []}],
    }


def instant_actions(version: str) -> dict[str, Any]:
    action = {"actionId": "a2", "actionType": "cancelOrder", "blockingType": "NONE"}
    if version == "2.0.0":
        action["actionName"] = "cancelOrder"  # 2.0.0's schema requires this name (its defect)
    return {**header(version), "actions": [action]}


def agv_position() -> dict[str, Any]:
    return {"x": 1.0, "y": 2.0, "theta": 0.5, "mapId": "floor1", "positionInitialized": True,
            "localizationScore": 0.9}


def state(version: str) -> dict[str, Any]:
    return {
        **header(version), "orderId": "robot1-1", "orderUpdateId": 0, "lastNodeId": "office_1",
        "lastNodeSequenceId": 0,
        "nodeStates": [{"nodeId": "room_201", "sequenceId": 2, "released": True}],
        "edgeStates": [{"edgeId": "e1", "sequenceId": 1, "released": True}],
        "driving": True, "agvPosition": agv_position(),
        "actionStates": [{"actionId": "a1", "actionStatus": "WAITING"}],
        "batteryState": {"batteryCharge": 81.5, "charging": False},
        "operatingMode": "AUTOMATIC",
        "errors": [{"errorType": "orderFailed", "errorLevel": "WARNING"}],
        "safetyState": {"eStop": "NONE", "fieldViolation": False},
    }


def visualization(version: str) -> dict[str, Any]:
    return {**header(version), "agvPosition": agv_position(),
            "velocity": {"vx": 0.3, "vy": 0.0, "omega": 0.1}}


def factsheet(version: str) -> dict[str, Any]:
    return {
        **header(version),
        "typeSpecification": {"seriesName": "polynav-sim", "agvKinematic": "DIFF",
                              "agvClass": "CARRIER", "maxLoadMass": 20.0,
                              "localizationTypes": ["NATURAL"], "navigationTypes": ["AUTONOMOUS"]},
        "physicalParameters": {"speedMin": 0.05, "speedMax": 1.0, "accelerationMax": 0.5,
                               "decelerationMax": 1.0, "heightMax": 1.2, "width": 0.5,
                               "length": 0.6},
        "protocolLimits": {"maxStringLens": {}, "maxArrayLens": {},
                           "timing": {"minOrderInterval": 1.0, "minStateInterval": 0.5}},
        "protocolFeatures": {
            "optionalParameters": [],
            "agvActions": [{"actionType": "cancelOrder", "actionScopes": ["INSTANT"]}],
        },
        "agvGeometry": {}, "loadSpecification": {},
    }


VALID = {"connection": connection, "order": order, "instantActions": instant_actions,
         "state": state, "visualization": visualization, "factsheet": factsheet}


def test_every_topic_has_an_example() -> None:
    assert set(VALID) == set(validation.TOPICS)


@pytest.mark.parametrize("version", validation.VERSIONS)
@pytest.mark.parametrize("topic", validation.TOPICS)
def test_valid_message_passes(topic: str, version: str) -> None:
    validation.validate(topic, version, VALID[topic](version))


@pytest.mark.parametrize("version", validation.VERSIONS)
@pytest.mark.parametrize("topic", validation.TOPICS)
def test_schema_ships_with_the_package_and_is_a_valid_schema(topic: str, version: str) -> None:
    root = importlib.resources.files("polynav.fleet.vda5050") / "schemas"
    document = json.loads((root / version / f"{topic}.schema").read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(document)
    assert document["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    assert validation.schema(topic, version) == document
    assert "Verband der Automobilindustrie" in (root / "LICENSE.txt").read_text(encoding="utf-8")


def _without(message: dict[str, Any], path: tuple[str | int, ...]) -> dict[str, Any]:
    out = copy.deepcopy(message)
    target: Any = out
    for step in path[:-1]:
        target = target[step]
    del target[path[-1]]
    return out


def _with(message: dict[str, Any], path: tuple[str | int, ...], value: Any) -> dict[str, Any]:
    out = copy.deepcopy(message)
    target: Any = out
    for step in path[:-1]:
        target = target[step]
    target[path[-1]] = value
    return out


MISSING = [  # (topic, path of the field removed, reported JSON path)
    ("connection", ("connectionState",), "$.connectionState"),
    ("order", ("nodes", 1, "released"), "$.nodes[1].released"),
    ("order", ("nodes", 0, "nodePosition", "mapId"), "$.nodes[0].nodePosition.mapId"),
    ("instantActions", ("actions", 0, "blockingType"), "$.actions[0].blockingType"),
    ("state", ("batteryState", "charging"), "$.batteryState.charging"),
    ("state", ("safetyState",), "$.safetyState"),
    ("visualization", ("agvPosition", "mapId"), "$.agvPosition.mapId"),
    ("factsheet", ("typeSpecification",), "$.typeSpecification"),
]


@pytest.mark.parametrize("version", validation.VERSIONS)
@pytest.mark.parametrize(("topic", "field", "expected"), MISSING)
def test_missing_required_field_is_named(
    topic: str, field: tuple[str | int, ...], expected: str, version: str
) -> None:
    with pytest.raises(SchemaViolation) as caught:
        validation.validate(topic, version, _without(VALID[topic](version), field))
    assert caught.value.path == expected
    assert caught.value.rule == "required"
    assert str(caught.value).startswith(f"{expected}: required: ")
    assert isinstance(caught.value, ValueError)


WRONG = [  # (topic, field, bad value, rule broken); every version
    ("connection", ("headerId",), "7", "type"),
    ("connection", ("connectionState",), "SLEEPING", "enum"),
    ("connection", ("timestamp",), 1764330003.12, "type"),
    ("connection", ("timestamp",), "2026-13-28T11:40:03Z", "format"),
    ("connection", ("timestamp",), "yesterday", "format"),
    ("order", ("orderUpdateId",), -1, "minimum"),
    ("order", ("nodes", 0, "sequenceId"), 1.5, "type"),
    ("order", ("nodes", 0, "nodePosition", "theta"), 4.0, "maximum"),
    ("order", ("nodes", 1, "actions", 0, "blockingType"), "MAYBE", "enum"),
    ("order", ("edges", 0, "released"), "yes", "type"),
    ("instantActions", ("actions",), {"actionId": "a"}, "type"),
    ("state", ("agvPosition", "localizationScore"), 1.5, "maximum"),
    ("state", ("agvPosition", "localizationScore"), -0.1, "minimum"),
    ("state", ("batteryState", "batteryCharge"), "full", "type"),
    ("state", ("operatingMode",), "AUTONOMOUS", "enum"),
    ("state", ("driving",), 1, "type"),
    ("visualization", ("agvPosition", "localizationScore"), 2, "maximum"),
    ("visualization", ("velocity", "vx"), "fast", "type"),
]


@pytest.mark.parametrize("version", validation.VERSIONS)
@pytest.mark.parametrize(("topic", "field", "value", "rule"), WRONG)
def test_wrong_type_or_out_of_range_value_is_named(
    topic: str, field: tuple[str | int, ...], value: Any, rule: str, version: str
) -> None:
    with pytest.raises(SchemaViolation) as caught:
        validation.validate(topic, version, _with(VALID[topic](version), field, value))
    path = "$" + "".join(f"[{s}]" if isinstance(s, int) else f".{s}" for s in field)
    assert (caught.value.path, caught.value.rule) == (path, rule)
    assert caught.value.topic == topic and caught.value.version == version


def test_factsheet_2_1_checks_inside_its_sections() -> None:
    bad = _with(factsheet("2.1.0"), ("typeSpecification", "maxLoadMass"), -1)
    with pytest.raises(SchemaViolation) as caught:
        validation.validate("factsheet", "2.1.0", bad)
    assert (caught.value.path, caught.value.rule) == ("$.typeSpecification.maxLoadMass",
                                                      "minimum")


def test_factsheet_2_0_checks_only_its_top_level_keys_as_published() -> None:
    # 2.0.0's factsheet schema lists its sections beside "properties", not inside: verbatim,
    # so a negative maxLoadMass passes there and fails in 2.1.0.
    bad = _with(factsheet("2.0.0"), ("typeSpecification", "maxLoadMass"), -1)
    validation.validate("factsheet", "2.0.0", bad)


def test_instant_actions_2_0_requires_action_name_as_published() -> None:
    with pytest.raises(SchemaViolation) as caught:
        validation.validate("instantActions", "2.0.0", instant_actions("2.1.0"))
    assert (caught.value.path, caught.value.rule) == ("$.actions[0].actionName", "required")


def test_a_message_that_is_not_an_object_is_refused() -> None:
    with pytest.raises(SchemaViolation) as caught:
        validation.validate("state", "2.1.0", ["not", "a", "state"])  # type: ignore[arg-type]
    assert (caught.value.path, caught.value.rule) == ("$", "type")


@pytest.mark.parametrize(("topic", "version", "field"), [
    ("zoneSet", "2.1.0", "topic"),
    ("order", "3.0.0", "version"),
    ("order", "2.1", "version"),
])
def test_unknown_topic_or_version_is_an_invalid_request(topic: str, version: str,
                                                        field: str) -> None:
    with pytest.raises(InvalidRequest) as caught:
        validation.validate(topic, version, {})
    assert caught.value.field == field
    assert not isinstance(caught.value, SchemaViolation)
