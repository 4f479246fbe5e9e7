from __future__ import annotations

import pytest

from polynav.errors import Conflict
from polynav.robot.sim.devices.software_update import SimSoftwareUpdate


def test_the_running_version_is_the_newest_and_an_update_is_refused() -> None:
    updater = SimSoftwareUpdate("0.1.0")
    assert updater.check() is None
    with pytest.raises(Conflict, match="no update available"):
        updater.start()
    assert updater.cancel() is False
    assert updater.log().splitlines() == [
        "checked for updates: 0.1.0 is the newest version",
        "update refused: no update available",
    ]
