"""The site store behind a runtime, as the dialects edit it.

The runtime is typed against the narrow :class:`~polynav.runtime.config.SiteData` (what it
reads); the dialects add, rename and delete maps and points, which the full
:class:`~polynav.store.site_store.SiteStore` does. ``polynav run`` always builds the runtime on a
``SiteStore``.
"""

from __future__ import annotations

from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore


def site_store(runtime: RobotRuntime) -> SiteStore:
    """``runtime``'s store.

    Raises:
        TypeError: the runtime runs on another store (a test double).
    """
    store = runtime.store
    if not isinstance(store, SiteStore):
        raise TypeError("the dialects serve a runtime backed by a SiteStore")
    return store
