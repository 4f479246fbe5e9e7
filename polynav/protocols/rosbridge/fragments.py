"""rosbridge's ``fragment`` op: long messages cut into pieces, and put back together.

A client sends ``{"op": "fragment", "id", "data", "num", "total"}`` pieces of one JSON message
(the pieces' ``data`` concatenated in ``num`` order); the server cuts an outgoing message the
same way when the subscriber asked for ``fragment_size``. Pieces are bounded: a client may
have :attr:`Reassembly.max_pending` messages half-sent, each no larger than the frame limit.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


class FragmentError(ValueError):
    """A piece that cannot be taken (the server answers with a status error)."""


@dataclass
class _Partial:
    total: int
    pieces: dict[int, str] = field(default_factory=dict)
    size: int = 0


class Reassembly:
    """One connection's half-received fragmented messages.

    Args:
        max_pending: messages that may be half-received at once.
        max_size: the largest message put back together [characters].
    """

    def __init__(self, max_pending: int, max_size: int) -> None:
        self.max_pending = max_pending
        self.max_size = max_size
        self._partial: dict[str, _Partial] = {}

    def add(self, frame: dict[str, Any]) -> str | None:
        """Take one piece; the whole message's text once its last piece is in.

        Raises:
            FragmentError: missing or mistyped fields, a piece out of range or disagreeing with
                the others, too many messages pending, a message beyond ``max_size``.
        """
        ident, data, num, total = (frame.get(k) for k in ("id", "data", "num", "total"))
        if not isinstance(ident, (str, int)) or isinstance(ident, bool):
            raise FragmentError("fragment: 'id' must be a string or an integer")
        if not isinstance(data, str):
            raise FragmentError("fragment: 'data' must be a string")
        if not isinstance(num, int) or not isinstance(total, int) or isinstance(num, bool) or (
                isinstance(total, bool)):
            raise FragmentError("fragment: 'num' and 'total' must be integers")
        if total < 1 or not 0 <= num < total:
            raise FragmentError(f"fragment: piece {num} of {total} is out of range")
        key = str(ident)
        partial = self._partial.get(key)
        if partial is None:
            if len(self._partial) >= self.max_pending:
                raise FragmentError(f"fragment: more than {self.max_pending} messages half-sent")
            partial = self._partial[key] = _Partial(total)
        elif partial.total != total:
            del self._partial[key]
            raise FragmentError(f"fragment {key}: 'total' changed from {partial.total} to {total}")
        if num not in partial.pieces:
            partial.size += len(data)
        partial.pieces[num] = data
        if partial.size > self.max_size:
            del self._partial[key]
            raise FragmentError(f"fragment {key}: the message exceeds {self.max_size} bytes")
        if len(partial.pieces) < total:
            return None
        del self._partial[key]
        return "".join(partial.pieces[i] for i in range(total))


def split(text: str, size: int, ident: str) -> list[dict[str, Any]]:
    """``text`` cut into ``fragment`` frames of at most ``size`` characters of data."""
    size = max(1, size)
    total = (len(text) + size - 1) // size
    return [{"op": "fragment", "id": ident, "data": text[i * size:(i + 1) * size], "num": i,
             "total": total} for i in range(total)]
