from __future__ import annotations

import math

import numpy as np

from polynav.geometry import Pose2D, Twist
from polynav.robot.interface import LaserScan, Odometry
from polynav.runtime import events
from polynav.runtime.watchers import DisplacementWatcher, ForeignObjectWatcher


def _odometry(x: float, speed: float = 0.0) -> Odometry:
    return Odometry(0.0, Pose2D(x, 0.0, 0.0), Twist(speed, 0.0))


def test_motion_without_a_command_is_reported_once_per_push() -> None:
    watcher = DisplacementWatcher()
    still, go = Twist(), Twist(0.5, 0.0)
    assert watcher.update(0.0, _odometry(0.0), still) is None
    # Braking after a command: a few centimetres, not a push.
    assert watcher.update(0.1, _odometry(0.05, 0.3), still) is None
    found = [watcher.update(0.2 + 0.1 * k, _odometry(0.05 + 0.05 * k, 0.3), still)
             for k in range(1, 10)]
    reported = [e for e in found if e is not None]
    assert len(reported) == 1 and isinstance(reported[0], events.RobotDisplaced)
    assert reported[0].distance >= 0.3
    assert watcher.update(2.0, _odometry(0.5), still) is None  # stands still: re-armed
    # Driving is not being pushed.
    for k in range(20):
        assert watcher.update(3.0 + 0.1 * k, _odometry(0.5 + 0.05 * k, 0.5), go) is None


def _scan(stamp: float, near: int) -> LaserScan:
    ranges = np.full(360, 5.0, dtype=np.float32)
    ranges[:near] = 0.06
    return LaserScan(stamp, -math.pi, math.radians(1.0), 0.05, 12.0, ranges)


def test_an_object_inside_the_housing_is_reported_once_until_it_is_gone() -> None:
    watcher = ForeignObjectWatcher(math.radians(10.0))
    assert watcher.update(0.0, _scan(0.0, 3)) is None  # a few beams: noise, not an object
    found = watcher.update(0.1, _scan(0.1, 40))
    assert isinstance(found, events.ForeignObjectDetected)
    assert math.isclose(found.sector, math.radians(40.0), rel_tol=1e-6)
    assert watcher.update(0.1, _scan(0.1, 40)) is None  # the same scan again
    assert watcher.update(0.2, _scan(0.2, 40)) is None  # still there: once
    assert watcher.update(0.3, _scan(0.3, 0)) is None
    assert watcher.update(0.4, _scan(0.4, 40)) is not None  # back again
