"""The compiled VDA 5050 schemas say valid exactly where jsonschema does.

The compiled checks are the fast path of every message written and read; jsonschema, which the
schemas were written for, is the reference. Each valid example is mutated at every field (a
wrong type, a value beyond a bound, a string not in an enum, a missing field, an extra field)
and both must agree on every mutant.
"""

from __future__ import annotations

import copy
from collections.abc import Iterator
from typing import Any

import jsonschema
import pytest

from polynav.fleet.vda5050 import compiled, validation
from tests.unit.fleet.test_vda_schemas import VALID

WRONG: tuple[object, ...] = (None, True, False, 0, -1, 1.0, 1.5, -1e9, 1e9, float("inf"), "",
                             "x", "NONE", "2026-13-40T99:00:00Z", "2026-11-28T11:40:03Z",
                             [], [1], ["x"], {}, {"x": 1})


def reference(topic: str, version: str) -> jsonschema.protocols.Validator:
    return validation._validator(topic, version)


def fast(topic: str, version: str) -> compiled.Check:
    check = validation._compiled(topic, version)
    assert check is not None, f"{version} {topic} did not compile: jsonschema on every message"
    return check


def mutants(value: Any) -> Iterator[Any]:
    """``value`` changed in one place each time, at every depth."""
    if isinstance(value, dict):
        for key in list(value):
            for wrong in WRONG:
                changed = copy.deepcopy(value)
                changed[key] = wrong
                yield changed
            without = copy.deepcopy(value)
            del without[key]
            yield without
            for inner in mutants(value[key]):
                changed = copy.deepcopy(value)
                changed[key] = inner
                yield changed
        yield {**copy.deepcopy(value), "extraField": 1}
    elif isinstance(value, list):
        for k, item in enumerate(value):
            for inner in (*WRONG, *mutants(item)):
                changed = copy.deepcopy(value)
                changed[k] = inner
                yield changed
        yield [*copy.deepcopy(value), *copy.deepcopy(value)]
        yield []


@pytest.mark.parametrize("version", validation.VERSIONS)
@pytest.mark.parametrize("topic", validation.TOPICS)
def test_compiled_check_agrees_with_jsonschema_on_every_mutant(topic: str,
                                                                version: str) -> None:
    check, ref = fast(topic, version), reference(topic, version)
    example = VALID[topic](version)
    assert check(example) and ref.is_valid(example)
    seen = invalid = 0
    for mutant in mutants(example):
        expected = ref.is_valid(mutant)
        assert check(mutant) == expected, (topic, version, mutant)
        seen += 1
        invalid += not expected
    assert invalid >= 5 and seen > invalid  # the mutants test both answers


@pytest.mark.parametrize("instance", [None, [], "state", 3, True])
def test_a_message_that_is_not_an_object_is_invalid_on_both(instance: object) -> None:
    assert not fast("state", "2.1.0")(instance)
    assert not reference("state", "2.1.0").is_valid(instance)


def test_a_refused_message_still_gets_jsonschemas_error_naming_the_field() -> None:
    message = VALID["state"]("2.0.0")
    message["batteryState"]["batteryCharge"] = "full"
    with pytest.raises(validation.SchemaViolation) as raised:
        validation.validate("state", "2.0.0", message)
    assert raised.value.path == "$.batteryState.batteryCharge"
    assert raised.value.rule == "type"


@pytest.mark.parametrize("schema", [
    {"anyOf": [{"type": "string"}]},
    {"type": "object", "additionalProperties": False},
    {"items": [{"type": "string"}]},
    {"$ref": "other.json#/x"},
    {"$ref": "#/definitions/missing"},
    {"type": "strung"},
    {"enum": [1, 2]},
])
def test_a_schema_beyond_the_compiler_is_refused_at_compile_time(
        schema: dict[str, Any]) -> None:
    with pytest.raises(compiled.NotCompilable):
        compiled.compile_schema(schema, {})


def test_integer_types_and_refs_follow_json_schema() -> None:
    schema = {"type": "object", "properties": {
        "n": {"type": "integer", "minimum": 0, "maximum": 10},
        "a": {"$ref": "#/definitions/a", "required": ["z"]}},
        "definitions": {"a": {"type": "object", "required": ["y"]}}}
    check = compiled.compile_schema(schema, {})
    ref = jsonschema.Draft202012Validator(schema)
    for instance in ({"n": 3.0}, {"n": 3.5}, {"n": True}, {"n": 11}, {"n": -0.0},
                     {"a": {"y": 1}}, {"a": {"z": 1}}, {"a": {"y": 1, "z": 2}}, {"a": 1}):
        assert check(instance) == ref.is_valid(instance), instance
