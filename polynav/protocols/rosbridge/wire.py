"""JSON as rosbridge clients read it: plain decimal numbers, keys in the message's order.

Some clients parse rosbridge JSON with regular expressions that expect ``0.00001``, never
``1e-05``, so every number in exponent form is rewritten in plain decimal form (outside
strings). Keys keep the order of the message dicts, which the encoders build in the ``.msg``
field order (``x, y, z`` then ``x, y, z, w``). NaN and infinities, which JSON cannot carry, are
written as ``null`` (rosbridge's own choice for float arrays; a LaserScan's "no return" reads
back as null, see docs/ros.md).
"""

from __future__ import annotations

import re
from decimal import Decimal
from typing import Any

import orjson

# A JSON string (skipped as it is) or a number in exponent form (rewritten).
_TOKEN = re.compile(rb'"(?:[^"\\]|\\.)*"|-?\d+(?:\.\d+)?[eE][+-]?\d+')
# Fast check: no digit directly followed by an exponent mark means nothing to rewrite.
_EXPONENT = re.compile(rb"\d[eE][+-]?\d")


def _plain(match: re.Match[bytes]) -> bytes:
    token = match.group(0)
    if token.startswith(b'"'):
        return token
    text = format(Decimal(token.decode("ascii")), "f")
    if "." not in text:
        text += ".0"  # it was a float: keep it one
    return text.encode("ascii")


def dumps(message: Any) -> str:
    """``message`` as rosbridge JSON text (see the module docstring)."""
    raw = orjson.dumps(message, option=orjson.OPT_SERIALIZE_NUMPY)
    if _EXPONENT.search(raw) is not None:
        raw = _TOKEN.sub(_plain, raw)
    return raw.decode("utf-8")


def loads(text: str | bytes) -> Any:
    """Parse a client's JSON frame.

    Raises:
        ValueError: not JSON.
    """
    try:
        return orjson.loads(text)
    except orjson.JSONDecodeError as exc:
        raise ValueError(f"invalid JSON: {exc}") from exc
