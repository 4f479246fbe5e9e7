"""Failures of the maps package.

A map file that cannot be read is a bad request from whoever named it (a user uploading a map, a
site directory edited by hand), so :class:`MapFormatError` is an :class:`InvalidRequest`: every
dialect already answers those with its own "bad parameter" error.
"""

from __future__ import annotations

from polynav.errors import InvalidRequest


class MapFormatError(InvalidRequest):
    """A map YAML or image is missing, unreadable, or has a missing or invalid field.

    ``field`` names the YAML key (``resolution``, ``origin`` ...), ``image`` for the picture, or
    ``yaml`` for the file as a whole.
    """
