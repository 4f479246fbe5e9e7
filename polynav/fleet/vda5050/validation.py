"""Check a VDA 5050 message against the standard's own JSON schema.

The schemas are the official ones, shipped verbatim in ``schemas/<version>/<topic>.schema``
(2.0.0's factsheet is ``factsheet.json`` upstream; it is renamed here so every topic has one
path). Each schema is compiled once per (topic, version) into plain Python checks
(:mod:`polynav.fleet.vda5050.compiled`, a few µs a message instead of ``jsonschema``'s 80-170 µs
walk); a message they refuse is checked again by ``jsonschema``, whose error is the one
reported. A message that breaks the schema raises :class:`SchemaViolation`, which names the
JSON path of the offending field and the schema rule it breaks, so whoever sent it can fix it.

The schemas declare ``"format": "date-time"`` for timestamps; JSON Schema 2020-12 treats formats
as annotations, and jsonschema checks ``date-time`` only with an optional extra package, so it is
checked here with a small RFC 3339 checker of our own: VDA 5050 §6.4 says timestamps are ISO 8601
in UTC ("2017-04-15T11:40:03.12Z").

The 2.0.0 schemas are shipped as published, defects included: its factsheet puts its
properties at the top level (only the nine top-level keys are required, their contents are
unchecked) and its instant actions require ``actionName`` where the text says ``actionType``.
Vehicles ship 2.1; 2.0.0 is there to read older vehicles' messages.
"""

from __future__ import annotations

import datetime
import functools
import importlib.resources
import json
import re
from typing import Any

import jsonschema

from polynav.errors import InvalidRequest
from polynav.fleet.vda5050 import compiled

TOPICS: tuple[str, ...] = (
    "connection", "factsheet", "state", "visualization", "order", "instantActions",
)
"""The VDA 5050 topics that have a schema."""

VERSIONS: tuple[str, ...] = ("2.0.0", "2.1.0")
"""The VDA 5050 versions whose schemas polynav ships."""

_RFC3339 = re.compile(
    r"\d{4}-\d{2}-\d{2}[Tt]\d{2}:\d{2}:\d{2}(\.\d+)?([Zz]|[+-]\d{2}:\d{2})\Z"
)


class SchemaViolation(InvalidRequest):
    """A message breaks its VDA 5050 schema.

    Attributes:
        topic: the message's topic (``"order"``...).
        version: the VDA 5050 version it was checked against.
        path: the JSON path of the offending field (``$.nodes[0].sequenceId``); for a missing
            field, the path the field should have had.
        rule: the schema keyword broken (``required``, ``type``, ``minimum``, ``enum``...).
    """

    def __init__(self, *, topic: str, version: str, path: str, rule: str, detail: str) -> None:
        super().__init__(path, f"{rule}: {detail} (VDA 5050 {version} {topic})")
        self.topic = topic
        self.version = version
        self.path = path
        self.rule = rule


def schema(topic: str, version: str) -> dict[str, Any]:
    """The official schema of ``topic`` in VDA 5050 ``version``, as parsed JSON.

    Raises:
        InvalidRequest: a topic or version polynav has no schema for.
    """
    return dict(_load(*_checked(topic, version)))


def validate(topic: str, version: str, message: dict[str, Any]) -> None:
    """Check ``message`` against the schema of ``topic`` in VDA 5050 ``version``.

    Args:
        topic: ``connection``, ``factsheet``, ``state``, ``visualization``, ``order`` or
            ``instantActions``.
        version: ``"2.0.0"`` or ``"2.1.0"``.
        message: the message as parsed JSON.

    Raises:
        SchemaViolation: the message breaks the schema; the first error by relevance.
        InvalidRequest: a topic or version polynav has no schema for.
    """
    key = _checked(topic, version)
    fast = _compiled(*key)
    if fast is not None and fast(message):
        return
    error = jsonschema.exceptions.best_match(_validator(*key).iter_errors(message))
    if error is None:
        return
    path = error.json_path
    rule = str(error.validator)
    if rule == "required" and isinstance(error.instance, dict):
        # Name the missing field itself, not only the object that lacks it.
        missing = [k for k in error.validator_value if k not in error.instance]
        if missing:
            path = f"{path}.{missing[0]}"
    raise SchemaViolation(topic=topic, version=version, path=path, rule=rule,
                          detail=error.message)


def _checked(topic: str, version: str) -> tuple[str, str]:
    if topic not in TOPICS:
        raise InvalidRequest("topic", f"no VDA 5050 schema for {topic!r}; one of {TOPICS}")
    if version not in VERSIONS:
        raise InvalidRequest("version", f"no VDA 5050 schemas for {version!r}; one of {VERSIONS}")
    return topic, version


@functools.cache
def _load(topic: str, version: str) -> dict[str, Any]:
    resource = importlib.resources.files(__package__) / "schemas" / version / f"{topic}.schema"
    loaded: dict[str, Any] = json.loads(resource.read_text(encoding="utf-8"))
    return loaded


@functools.cache
def _compiled(topic: str, version: str) -> compiled.Check | None:
    """The schema as closures (:mod:`.compiled`), None if it uses more than they implement
    (then jsonschema checks every message)."""
    try:
        return compiled.compile_schema(_load(topic, version), {"date-time": _is_date_time})
    except compiled.NotCompilable:
        return None


@functools.cache
def _validator(topic: str, version: str) -> jsonschema.protocols.Validator:
    document = _load(topic, version)
    cls = jsonschema.validators.validator_for(document)
    cls.check_schema(document)
    return cls(document, format_checker=_FORMATS)


def _is_date_time(value: object) -> bool:
    if not isinstance(value, str):
        return True  # "format" constrains strings only; "type" catches the rest
    if not _RFC3339.match(value):
        return False
    try:
        datetime.datetime.fromisoformat(value.upper().replace("Z", "+00:00"))
    except ValueError:  # e.g. month 13, 25 o'clock
        return False
    return True


_FORMATS = jsonschema.FormatChecker(formats=())
_FORMATS.checks("date-time")(_is_date_time)
