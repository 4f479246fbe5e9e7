"""Fleet messages to VDA 5050 JSON and back: camelCase keys, enums as their strings.

Pure: bytes in, typed messages out, no I/O. The in-process transport sends every message through
here, so the messages polynav's robots exchange today are the bytes an MQTT broker would carry.
Bad input raises :class:`~polynav.errors.InvalidRequest` naming the field.
"""

from __future__ import annotations

import dataclasses
import enum
import functools
import types
import typing
from typing import Any

import orjson

from polynav.errors import InvalidRequest
from polynav.fleet import messages
from polynav.fleet.messages import Message

_BY_TOPIC: dict[str, type] = {name: kind for kind, name in messages.TOPICS.items()}


def encode(message: Message) -> bytes:
    """The JSON of ``message`` (VDA 5050 names)."""
    return orjson.dumps(_to_json(message))


def decode(kind: str, data: bytes) -> Message:
    """The message of topic suffix ``kind`` (``"order"``, ``"state"``...) in ``data``.

    Raises:
        InvalidRequest: unknown kind, not JSON, a field missing or of the wrong type.
    """
    target = _BY_TOPIC.get(kind)
    if target is None:
        raise InvalidRequest("topic", f"unknown message kind {kind!r}")
    try:
        raw = orjson.loads(data)
    except orjson.JSONDecodeError as exc:
        raise InvalidRequest("message", f"not JSON: {exc}") from None
    message: Message = _from_json(target, raw, kind)
    return message


def _camel(name: str) -> str:
    head, *rest = name.split("_")
    return head + "".join(part.capitalize() for part in rest)


def _to_json(value: object) -> Any:
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {_camel(f.name): _to_json(getattr(value, f.name))
                for f in dataclasses.fields(value)}
    if isinstance(value, enum.Enum):
        return value.value
    if isinstance(value, tuple):
        return [_to_json(v) for v in value]
    return value


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
            if key not in raw:
                if required:
                    raise InvalidRequest(f"{where}.{key}", "missing")
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
    if kind is str:
        if not isinstance(raw, str):
            raise InvalidRequest(where, "must be a string")
        return raw
    raise InvalidRequest(where, f"cannot read a {kind!r}")  # a message type polynav lacks
