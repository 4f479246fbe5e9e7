"""Controllers by name, so configuration picks one without ``isinstance`` chains (STYLE R2).

Like Nav2's ``controller_plugins``: the navigation stack names a controller in its configuration,
and :func:`create` builds it with that controller's own configuration.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

from polynav.control.interface import Controller
from polynav.control.pure_pursuit import PurePursuitConfig, RegulatedPurePursuit
from polynav.errors import ConfigError

log = logging.getLogger(__name__)


def _regulated_pure_pursuit(config: Any = None) -> Controller:
    if config is not None and not isinstance(config, PurePursuitConfig):
        raise ConfigError(
            "control.pure_pursuit", f"expected a PurePursuitConfig, got {type(config).__name__}"
        )
    return RegulatedPurePursuit(config)


CONTROLLERS: dict[str, Callable[..., Controller]] = {
    "regulated_pure_pursuit": _regulated_pure_pursuit,
}
"""Factories by name; each takes its controller's config (or ``None`` for the defaults)."""


def create(name: str, config: Any = None) -> Controller:
    """The controller registered as ``name``, built with ``config``.

    Raises:
        ConfigError: an unknown name, or a config of the wrong type for that controller.
    """
    try:
        factory = CONTROLLERS[name]
    except KeyError:
        known = ", ".join(sorted(CONTROLLERS))
        raise ConfigError(
            "control.controller", f"unknown controller {name!r} (known: {known})"
        ) from None
    return factory(config)
