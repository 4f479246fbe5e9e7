"""The runtime's settings: read them, the stack configuration they give, and change them.

Part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` (see
:mod:`~polynav.runtime.internals`). Settings are persisted in the site store and applied
between ticks; the navigation stack takes them between goals, so a running goal finishes with
the values it started with (the control tick rebuilds the stack once no goal runs).
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Mapping

from polynav.nav.stack import StackConfig
from polynav.robot.profile import RobotProfile
from polynav.runtime.internals import RuntimeParts
from polynav.runtime.settings import RobotSettings

log = logging.getLogger(__name__)


class SettingsCommands(RuntimeParts):
    """Reading and changing the robot's settings (set up by the runtime)."""

    profile: RobotProfile
    _settings_lock: threading.Lock

    def settings(self) -> RobotSettings:
        return self._settings

    def stack_config(self) -> StackConfig:
        """The navigation stack's configuration under the current settings (the planner and
        costmap a query should use to answer as the robot would plan)."""
        return self._settings.stack_config(self._base_stack_config)

    def update_settings(self, changes: Mapping[str, object]) -> RobotSettings:
        """Validate, persist and apply ``changes``; returns the new settings.

        Speed limits for teleop apply at once; the navigation stack takes the new values
        between goals (a running goal finishes with the old ones).

        Raises:
            InvalidRequest: unknown name, wrong type or out of range (``field`` names it).
            BeyondProfile: a speed above the robot profile's limits, a planning footprint
                below its body.
        """
        with self._settings_lock:
            new = self._settings.apply(changes, self.profile)
            stored = new.to_dict()
            self.store.update_settings({key: stored[key] for key in changes})

            def run() -> None:
                self._settings = new
                self._settings_dirty = True
                if self._stack is not None and not self._goal_active():
                    self._rebuild_stack()

            self._call(run)
        log.info("settings updated: %s", dict(changes))
        return new
