"""One Puwei request as handlers see it: path parameters, query, JSON body, uploaded files.

Puwei puts names and values in the path (``/api/param/set/:name/:value``, puwei-api §2.3) and
task definitions in a JSON body (``POST /api/task/set``). The body is read and parsed before the
handler runs (on the event loop); a body that is not JSON is refused here with the field named.
Query flags take the words real clients send: ``true``/``false``, ``1``/``0``.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from polynav.errors import InvalidRequest

_TRUE = {"true", "1", "yes", "on"}
_FALSE = {"false", "0", "no", "off"}
_MISSING: Any = object()


@dataclass(frozen=True, slots=True)
class UploadedFile:
    """A file part of a multipart request."""

    filename: str
    content: bytes


@dataclass(frozen=True, slots=True)
class PuweiRequest:
    """The parts of one request.

    Attributes:
        path: the path parameters (``name``, ``value``), percent-decoded.
        query: the query string.
        body: the parsed JSON body, ``None`` without one.
        has_body: whether a (non-blank) JSON body came.
        form: multipart or urlencoded text fields.
        files: multipart file parts, by field name.
    """

    path: Mapping[str, str] = field(default_factory=dict)
    query: Mapping[str, str] = field(default_factory=dict)
    body: Any = None
    has_body: bool = False
    form: Mapping[str, str] = field(default_factory=dict)
    files: Mapping[str, UploadedFile] = field(default_factory=dict)

    def name(self, key: str = "name") -> str:
        """A path parameter, not blank.

        Raises:
            InvalidRequest: missing or blank.
        """
        value = self.path.get(key, "")
        if not value.strip():
            raise InvalidRequest(key, "must not be empty")
        return value

    def flag(self, key: str, default: bool) -> bool:
        """A query flag: ``true``/``false``/``1``/``0`` (any case); ``default`` when absent.

        Raises:
            InvalidRequest: another word.
        """
        value = self.query.get(key)
        if value is None:
            return default
        word = value.strip().lower()
        if word in _TRUE:
            return True
        if word in _FALSE:
            return False
        raise InvalidRequest(key, f"must be true or false, got {value!r}")

    def json_object(self) -> dict[str, Any]:
        """The JSON body, which must be an object.

        Raises:
            InvalidRequest: no body, or not an object.
        """
        if not self.has_body:
            raise InvalidRequest("body", "a JSON object is required (Content-Type: "
                                         "application/json)")
        if not isinstance(self.body, dict):
            raise InvalidRequest("body", f"must be a JSON object, got {type_name(self.body)}")
        return self.body


def parse_body(raw: bytes) -> tuple[Any, bool]:
    """(the parsed JSON, whether there was any) of a request body.

    Raises:
        InvalidRequest: not UTF-8 JSON, or NaN/Infinity in it.
    """
    if not raw.strip():
        return None, False
    try:
        value = json.loads(raw, parse_constant=_no_constant)
    except (ValueError, UnicodeDecodeError) as exc:
        raise InvalidRequest("body", f"must be JSON: {exc}") from None
    return value, True


def _no_constant(name: str) -> Any:
    raise ValueError(f"{name} is not a JSON number")


def type_name(value: object) -> str:
    """The JSON type of ``value``, for messages."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, (int, float)):
        return "number"
    if isinstance(value, str):
        return "string"
    if isinstance(value, list):
        return "array"
    return "object"


def number(text: str, key: str) -> float:
    """A finite decimal number from path or query text.

    Raises:
        InvalidRequest: not one.
    """
    try:
        value = float(text.strip())
    except ValueError:
        raise InvalidRequest(key, f"must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise InvalidRequest(key, f"must be a finite number, got {text!r}")
    return value
