"""A VDA 5050 schema compiled to nested Python checks: is a message valid, in microseconds.

``jsonschema`` walks the schema for every message, building a validator object per keyword
and sub-document it descends into: about 80 µs for a visualization and 170 µs for an idle
state, most of a light vehicle's process at 1,000 vehicles (each message checked when written
and again when read). The official VDA 5050 schemas use a small part of JSON Schema
(``type``, ``properties``, ``required``, ``items``, ``enum``, ``minimum``, ``maximum``,
``format`` and a ``$ref`` into ``definitions``), so :func:`compile_schema` turns one into a
tree of closures once, which answers only *whether* a message is valid (2-10 µs); a message it
refuses is then checked again by ``jsonschema`` for the error a sender can act on
(:mod:`polynav.fleet.vda5050.validation`).

The meaning is JSON Schema 2020-12's, as ``jsonschema`` applies it: a keyword constrains only
the instances of its type (``minimum`` a number, ``required`` an object...); ``integer`` is
a whole number, ``1.0`` included; booleans are neither numbers nor integers; ``$ref`` is
applied beside its sibling keywords. A schema using any other keyword is refused at compile
time (:class:`NotCompilable`), so the caller keeps ``jsonschema`` for it rather than check
less than the schema says.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

Check = Callable[[Any], bool]
"""A compiled schema: whether an instance (parsed JSON) is valid."""

IMPLEMENTED = frozenset({
    "type", "properties", "required", "items", "enum", "minimum", "maximum", "format", "$ref",
})
"""The keywords that constrain an instance and are compiled here."""

NOT_IMPLEMENTED = frozenset({
    "$anchor", "$dynamicRef", "$dynamicAnchor", "$recursiveRef", "$vocabulary", "allOf",
    "anyOf", "oneOf", "not", "if", "then", "else", "dependentSchemas", "dependencies",
    "prefixItems", "additionalItems", "contains", "patternProperties", "additionalProperties",
    "propertyNames", "const", "multipleOf", "exclusiveMaximum", "exclusiveMinimum",
    "maxLength", "minLength", "pattern", "maxItems", "minItems", "uniqueItems", "maxContains",
    "minContains", "maxProperties", "minProperties", "dependentRequired", "unevaluatedItems",
    "unevaluatedProperties", "contentSchema",
})
"""The other keywords of JSON Schema 2020-12 (and draft 7's) that constrain an instance: a
schema using one is not compiled. Every other key is an annotation to a validator (``title``,
``unit``, and 2.0.0's factsheet's properties written at the top level, as published)."""


class NotCompilable(Exception):
    """The schema uses a keyword (or a form of one) this compiler does not implement."""


def compile_schema(schema: Mapping[str, Any],
                   formats: Mapping[str, Callable[[object], bool]]) -> Check:
    """``schema`` as one check.

    Args:
        schema: a whole schema document (its ``$ref`` s resolve within it).
        formats: a checker per ``format`` name to apply; formats not named are annotations
            (JSON Schema 2020-12's default).

    Raises:
        NotCompilable: a keyword or a ``$ref`` outside what this module implements.
    """
    return _Compiler(schema, formats).compile(schema)


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _is_integer(value: object) -> bool:
    if isinstance(value, bool):
        return False
    if isinstance(value, int):
        return True
    return isinstance(value, float) and value.is_integer()


_TYPES: dict[str, Callable[[object], bool]] = {
    "object": lambda v: isinstance(v, dict),
    "array": lambda v: isinstance(v, list),
    "string": lambda v: isinstance(v, str),
    "boolean": lambda v: isinstance(v, bool),
    "number": _is_number,
    "integer": _is_integer,
    "null": lambda v: v is None,
}


class _Compiler:
    def __init__(self, root: Mapping[str, Any],
                 formats: Mapping[str, Callable[[object], bool]]) -> None:
        self.root = root
        self.formats = formats
        self.refs: dict[str, Check] = {}

    def compile(self, schema: object) -> Check:
        if schema is True:
            return lambda _v: True
        if schema is False:
            return lambda _v: False
        if not isinstance(schema, Mapping):
            raise NotCompilable(f"a schema must be an object or a boolean, got {schema!r}")
        unknown = NOT_IMPLEMENTED.intersection(schema)
        if unknown:
            raise NotCompilable(f"keywords not implemented: {sorted(unknown)}")
        checks: list[Check] = []
        if "type" in schema:
            checks.append(self._type(schema["type"]))
        if "enum" in schema:
            checks.append(_enum(schema["enum"]))
        if "minimum" in schema or "maximum" in schema:
            checks.append(_bounds(schema.get("minimum"), schema.get("maximum")))
        if "format" in schema and schema["format"] in self.formats:
            fmt = self.formats[schema["format"]]
            checks.append(lambda v: not isinstance(v, str) or fmt(v))
        if "required" in schema:
            required = tuple(schema["required"])
            checks.append(lambda v: not isinstance(v, dict) or all(k in v for k in required))
        if "properties" in schema:
            checks.append(self._properties(schema["properties"]))
        if "items" in schema:
            checks.append(self._items(schema["items"]))
        if "$ref" in schema:
            checks.append(self._ref(schema["$ref"]))
        return _all(checks)

    def _type(self, spec: object) -> Check:
        names = [spec] if isinstance(spec, str) else spec
        if not isinstance(names, list) or not all(n in _TYPES for n in names):
            raise NotCompilable(f"type {spec!r}")
        tests = tuple(_TYPES[n] for n in names)
        if len(tests) == 1:
            return tests[0]
        return lambda v: any(t(v) for t in tests)

    def _properties(self, spec: object) -> Check:
        if not isinstance(spec, Mapping):
            raise NotCompilable("properties must be an object")
        props = tuple((key, self.compile(sub)) for key, sub in spec.items())

        def check(value: Any) -> bool:
            if not isinstance(value, dict):
                return True
            for key, sub in props:
                if key in value and not sub(value[key]):
                    return False
            return True
        return check

    def _items(self, spec: object) -> Check:
        if not isinstance(spec, (Mapping, bool)):
            raise NotCompilable("items must be a schema (2020-12), not a list")
        item = self.compile(spec)
        return lambda v: not isinstance(v, list) or all(item(x) for x in v)

    def _ref(self, ref: object) -> Check:
        if not isinstance(ref, str) or not ref.startswith("#/"):
            raise NotCompilable(f"$ref {ref!r}: only pointers into this document")
        if ref not in self.refs:
            target: Any = self.root
            for part in ref[2:].split("/"):
                part = part.replace("~1", "/").replace("~0", "~")
                if not isinstance(target, Mapping) or part not in target:
                    raise NotCompilable(f"$ref {ref!r} points nowhere")
                target = target[part]
            # Placeholder first: a schema that refers to itself compiles to a loop, not forever.
            slot: list[Check] = []
            self.refs[ref] = lambda v: slot[0](v)
            slot.append(self.compile(target))
        return self.refs[ref]


def _enum(values: object) -> Check:
    if not isinstance(values, list) or not all(isinstance(x, str) for x in values):
        raise NotCompilable("enum: only lists of strings are implemented")
    allowed = frozenset(values)
    return lambda v: isinstance(v, str) and v in allowed


def _bounds(low: object, high: object) -> Check:
    for bound in (low, high):
        if bound is not None and not _is_number(bound):
            raise NotCompilable(f"bound {bound!r} is not a number")

    def check(value: Any) -> bool:
        if not _is_number(value):
            return True
        if low is not None and value < low:
            return False
        return not (high is not None and value > high)
    return check


def _all(checks: list[Check]) -> Check:
    if not checks:
        return lambda _v: True
    if len(checks) == 1:
        return checks[0]
    bound = tuple(checks)
    return lambda v: all(c(v) for c in bound)
