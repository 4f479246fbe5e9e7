from __future__ import annotations

from polynav.geometry import Twist
from polynav.runtime.teleop import Teleop


def test_a_command_holds_until_the_timeout_then_expires() -> None:
    teleop = Teleop(0.5)
    teleop.command(Twist(0.3, 0.1), now=10.0)
    assert teleop.twist(10.49) == Twist(0.3, 0.1)
    assert teleop.twist(10.5) is None
    assert not teleop.active


def test_a_repeated_command_extends_the_deadline() -> None:
    teleop = Teleop(0.5)
    teleop.command(Twist(0.2, 0.0), now=0.0)
    teleop.command(Twist(0.1, 0.0), now=0.4)
    assert teleop.twist(0.8) == Twist(0.1, 0.0)
    assert teleop.twist(0.9) is None


def test_stop_forgets_the_command_at_once() -> None:
    teleop = Teleop(0.5)
    teleop.command(Twist(0.2, 0.0), now=0.0)
    teleop.stop()
    assert teleop.twist(0.1) is None
