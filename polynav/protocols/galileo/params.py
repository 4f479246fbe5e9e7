"""Request parameters, as Galileo clients send them, with typed accessors.

The spec (galileo-http-a §1.1): GET and DELETE carry parameters in the query string, POST and
PUT in a JSON body; real clients mix both, so every request's parameters are the query string
overlaid by the JSON body (the body wins on a clash) and, for multipart uploads, the form
fields, with the files apart. Query values are strings; the accessors parse them (numbers in
decimal, booleans as ``true``/``false``/``1``/``0``, A-40) and accept the JSON types a body
carries. A missing or mistyped parameter raises :class:`~polynav.errors.InvalidRequest` naming
it, which the HTTP layer answers in the documented error shape.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from polynav.errors import InvalidRequest

_MISSING: Any = object()
_TRUE = {"true", "1", "yes", "on"}
_FALSE = {"false", "0", "no", "off"}


@dataclass(frozen=True, slots=True)
class UploadedFile:
    """A file part of a multipart request."""

    filename: str
    content: bytes
    content_type: str = "application/octet-stream"


@dataclass(frozen=True, slots=True)
class Params:
    """The parameters of one request.

    Attributes:
        values: name -> value (strings from the query string and form, JSON values from a
            body).
        files: multipart file parts by field name.
        body: the parsed JSON body when it was not an object (some endpoints take a list).
    """

    values: Mapping[str, Any] = field(default_factory=dict)
    files: Mapping[str, UploadedFile] = field(default_factory=dict)
    body: Any = None

    def __contains__(self, name: str) -> bool:
        return name in self.values and self.values[name] is not None

    def raw(self, name: str, default: Any = _MISSING) -> Any:
        """The value as sent; ``default`` when absent (required when no default)."""
        value = self.values.get(name)
        if value is None:
            if default is _MISSING:
                raise InvalidRequest(name, "required parameter is missing")
            return default
        return value

    def text(self, name: str, default: Any = _MISSING) -> Any:
        """A string (numbers sent in a body are taken as their decimal text)."""
        value = self.raw(name, default)
        if value is default and default is not _MISSING:
            return value
        if isinstance(value, bool) or isinstance(value, (dict, list)):
            raise InvalidRequest(name, f"must be a string, got {_show(value)}")
        return str(value)

    def integer(self, name: str, default: Any = _MISSING) -> Any:
        """An int; ``"3"`` and ``3`` are accepted, ``3.5``, ``true`` and ``"x"`` are not."""
        value = self.raw(name, default)
        if value is default and default is not _MISSING:
            return value
        if isinstance(value, bool):
            raise InvalidRequest(name, f"must be an integer, got {_show(value)}")
        if isinstance(value, int):
            return value
        if isinstance(value, float) and value.is_integer():
            return int(value)
        if isinstance(value, str):
            try:
                return int(value.strip())
            except ValueError:
                pass
        raise InvalidRequest(name, f"must be an integer, got {_show(value)}")

    def number(self, name: str, default: Any = _MISSING) -> Any:
        """A finite float."""
        value = self.raw(name, default)
        if value is default and default is not _MISSING:
            return value
        if isinstance(value, bool):
            raise InvalidRequest(name, f"must be a number, got {_show(value)}")
        result: float | None = None
        if isinstance(value, (int, float)):
            result = float(value)
        elif isinstance(value, str):
            try:
                result = float(value.strip())
            except ValueError:
                result = None
        if result is None or not math.isfinite(result):
            raise InvalidRequest(name, f"must be a finite number, got {_show(value)}")
        return result

    def boolean(self, name: str, default: Any = _MISSING) -> Any:
        """A bool: JSON ``true``/``false``, ``1``/``0``, or those words in any case."""
        value = self.raw(name, default)
        if value is default and default is not _MISSING:
            return value
        if isinstance(value, bool):
            return value
        if isinstance(value, (int, float)) and value in (0, 1):
            return bool(value)
        if isinstance(value, str):
            word = value.strip().lower()
            if word in _TRUE:
                return True
            if word in _FALSE:
                return False
        raise InvalidRequest(name, f"must be true or false, got {_show(value)}")

    def structure(self, name: str, default: Any = _MISSING) -> Any:
        """A JSON list or object, sent as JSON in a body or as JSON text in the query."""
        value = self.raw(name, default)
        if value is default and default is not _MISSING:
            return value
        if isinstance(value, str):
            try:
                value = json.loads(value)
            except ValueError as exc:
                raise InvalidRequest(name, f"must be JSON: {exc}") from None
        if not isinstance(value, (list, dict)):
            raise InvalidRequest(name, f"must be a JSON list or object, got {_show(value)}")
        return value

    def file(self, name: str) -> UploadedFile:
        """A multipart file part (required)."""
        upload = self.files.get(name)
        if upload is None:
            raise InvalidRequest(name, "required file part is missing (multipart/form-data)")
        return upload


def _show(value: object) -> str:
    text = json.dumps(value, ensure_ascii=False) if not isinstance(value, str) else repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
