"""Fleet messages to VDA 5050 JSON and back: camelCase keys, enums as their strings.

Pure: bytes in, typed messages out, no I/O. Every transport sends every message through here, so
the in-process building exchanges the bytes an MQTT broker would carry. A message's ``header``
is written as the standard's top-level header fields; fields that are None are left out.

Messages on the standard's topics (order, instantActions, state, connection, visualization) are
checked against the official schema of their header's version both ways
(:mod:`polynav.fleet.vda5050.validation`): a message polynav writes that breaks it is a bug and
raises; one it reads that breaks it is refused like any bad input, with
:class:`~polynav.errors.InvalidRequest` naming the field (a
:class:`~polynav.fleet.vda5050.validation.SchemaViolation` for a schema rule). 2.0.0's instant
actions name their type ``actionName`` (its schema's defect, kept): polynav writes both names
and reads either.
"""

from __future__ import annotations

import contextlib
import dataclasses
import enum
import functools
import types
import typing
from typing import Any

import orjson

from polynav.errors import InvalidRequest
from polynav.fleet import messages
from polynav.fleet.messages import Message, Received, Rejected
from polynav.fleet.vda5050 import validation

_BY_TOPIC: dict[str, type] = {name: kind for kind, name in messages.TOPICS.items()}


def encode(message: Message) -> bytes:
    """The JSON of ``message`` (VDA 5050 names), checked against its schema if it has one.

    Raises:
        SchemaViolation: the message breaks its version's schema (a bug in its sender).
    """
    return orjson.dumps(to_json(message))


def to_json(message: Message) -> dict[str, Any]:
    """``message`` as parsed JSON, checked against its schema if it has one (as :func:`encode`)."""
    raw: dict[str, Any] = _to_json(message)
    kind = messages.TOPICS[type(message)]
    header = getattr(message, "header", None)
    if isinstance(header, messages.Header):
        if kind == "instantActions" and header.version == "2.0.0":
            for action in raw["actions"]:
                action["actionName"] = action["actionType"]
        validation.validate(kind, header.version, raw)
    return raw


def decode(kind: str, data: bytes) -> Message:
    """The message of topic suffix ``kind`` (``"order"``, ``"state"``...) in ``data``.

    Raises:
        InvalidRequest: unknown kind, not JSON, a field missing or of the wrong type, a VDA 5050
            version polynav has no schema for; SchemaViolation (an InvalidRequest) for a message
            that breaks its version's schema.
    """
    target = _BY_TOPIC.get(kind)
    if target is None:
        raise InvalidRequest("topic", f"unknown message kind {kind!r}")
    try:
        raw = orjson.loads(data)
    except orjson.JSONDecodeError as exc:
        raise InvalidRequest("message", f"not JSON: {exc}") from None
    if kind in validation.TOPICS:
        if not isinstance(raw, dict):
            raise InvalidRequest(kind, "must be an object")
        version = raw.get("version")
        if version not in validation.VERSIONS:
            raise InvalidRequest(f"{kind}.version",
                                 f"{version!r}: polynav speaks {', '.join(validation.VERSIONS)}")
        validation.validate(kind, version, raw)
        if kind == "instantActions" and version == "2.0.0":
            for action in raw["actions"]:
                action.setdefault("actionType", action.get("actionName"))
    message: Message = _from_json(target, raw, kind)
    return message


def read(kind: str, data: bytes) -> Received:
    """:func:`decode`, with a message that cannot be used handed back as a
    :class:`~polynav.fleet.messages.Rejected` (what could be read of its header and order id
    kept for the report) instead of raised."""
    try:
        return decode(kind, data)
    except InvalidRequest as exc:
        header_id = order_id = None
        with contextlib.suppress(orjson.JSONDecodeError):
            raw = orjson.loads(data)
            if isinstance(raw, dict):
                got_id, got_order = raw.get("headerId"), raw.get("orderId")
                header_id = got_id if isinstance(got_id, int) else None
                order_id = got_order if isinstance(got_order, str) else None
        return Rejected(kind, exc.field, str(exc), header_id, order_id)


def _camel(name: str) -> str:
    head, *rest = name.split("_")
    return head + "".join(part.capitalize() for part in rest)


def _to_json(value: object) -> Any:
    names = _json_names(type(value))
    if names is not None:
        out: dict[str, Any] = {}
        for name, key in names:
            item = getattr(value, name)
            if item is None:
                continue
            if key is None:  # the header: its fields at the top level
                out.update(_to_json(item))
            else:
                out[key] = _to_json(item)
        return out
    if isinstance(value, enum.Enum):
        return value.value
    if isinstance(value, tuple):
        return [_to_json(v) for v in value]
    return value


_NAMES: dict[type, tuple[tuple[str, str | None], ...] | None] = {}


def _json_names(kind: type) -> tuple[tuple[str, str | None], ...] | None:
    """Per field of a message dataclass: its name and JSON key (None for the header, written
    inline); None for a type that is not a dataclass. Read once per class: asking
    ``dataclasses`` and camel-casing every field of every message was most of writing one."""
    try:
        return _NAMES[kind]
    except KeyError:
        pass
    names = (tuple((f.name, None if f.name == "header" else _camel(f.name))
                   for f in dataclasses.fields(kind))
             if dataclasses.is_dataclass(kind) else None)
    _NAMES[kind] = names
    return names


@functools.cache
def _fields(kind: type) -> tuple[tuple[str, str, Any, bool], ...]:
    """Per field of a message dataclass: name, JSON key, type, required; read once per class
    (resolving the type hints is most of the cost of decoding a message)."""
    hints = typing.get_type_hints(kind, vars(messages))
    return tuple(
        (f.name, _camel(f.name), hints[f.name],
         f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING)
        for f in dataclasses.fields(kind)
    )


def _optional(hint: Any) -> bool:
    return typing.get_origin(hint) in (typing.Union, types.UnionType) and (
        type(None) in typing.get_args(hint))


def _from_json(kind: Any, raw: Any, where: str) -> Any:
    origin = typing.get_origin(kind)
    if origin in (typing.Union, types.UnionType):
        options = typing.get_args(kind)
        if raw is None and type(None) in options:
            return None
        (inner,) = [o for o in options if o is not type(None)]
        return _from_json(inner, raw, where)
    if origin is tuple:
        if not isinstance(raw, list):
            raise InvalidRequest(where, "must be a list")
        (inner, _) = typing.get_args(kind)
        return tuple(_from_json(inner, item, f"{where}[{k}]") for k, item in enumerate(raw))
    if isinstance(kind, type) and dataclasses.is_dataclass(kind):
        if not isinstance(raw, dict):
            raise InvalidRequest(where, "must be an object")
        values = {}
        for name, key, hint, required in _fields(kind):
            if name == "header":
                values[name] = _from_json(hint, raw, where)
                continue
            if key not in raw:
                if required and not _optional(hint):
                    raise InvalidRequest(f"{where}.{key}", "missing")
                if required:  # an optional field without a default: absent is None
                    values[name] = None
                continue
            values[name] = _from_json(hint, raw[key], f"{where}.{key}")
        return kind(**values)
    if isinstance(kind, type) and issubclass(kind, enum.Enum):
        try:
            return kind(raw)
        except ValueError:
            raise InvalidRequest(where, f"unknown value {raw!r}") from None
    if kind is float:
        if isinstance(raw, bool) or not isinstance(raw, (int, float)):
            raise InvalidRequest(where, "must be a number")
        return float(raw)
    if kind is int:
        if isinstance(raw, bool) or not isinstance(raw, int):
            raise InvalidRequest(where, "must be an integer")
        return raw
    if kind is bool:
        if not isinstance(raw, bool):
            raise InvalidRequest(where, "must be true or false")
        return raw
    if kind is object:
        return raw
    if kind is str:
        if not isinstance(raw, str):
            raise InvalidRequest(where, "must be a string")
        return raw
    raise InvalidRequest(where, f"cannot read a {kind!r}")  # a message type polynav lacks
