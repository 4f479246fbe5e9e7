"""Failures of the mapping package: unreadable logs and bad evaluation input."""

from __future__ import annotations

from polynav.errors import PolynavError


class LogError(PolynavError):
    """A sensor log cannot be used: missing, in an unknown format, or with no scans."""


class EmptyLogError(LogError):
    """A log holds no usable laser scan (an empty file, or only comments and corrupt lines)."""


class RelationsError(PolynavError):
    """A trajectory or relations file for :mod:`polynav.mapping.evaluation` is unusable."""
