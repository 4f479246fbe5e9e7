"""Failures of the worlds package.

A world folder that cannot be read is a bad request from whoever named it (a user pointing
``polynav run --world`` at a folder), so :class:`WorldFormatError` is an
:class:`~polynav.errors.InvalidRequest`, like a bad map file.
"""

from __future__ import annotations

from polynav.errors import InvalidRequest


class WorldFormatError(InvalidRequest):
    """A ``world.yaml`` is missing, unreadable, or has a missing or invalid field.

    ``field`` names the key path (``floors[1].points[3].kind``), or ``world.yaml`` for the file.
    """
