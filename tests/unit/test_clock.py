from __future__ import annotations

import pytest

from polynav.clock import ManualClock


def test_manual_clock_moves_only_when_advanced() -> None:
    clock = ManualClock(5.0)
    assert clock.now() == 5.0
    assert clock.advance(0.25) == 5.25
    clock.set(7.0)
    assert clock.now() == 7.0


def test_manual_clock_never_runs_backwards() -> None:
    clock = ManualClock(1.0)
    with pytest.raises(ValueError):
        clock.advance(-0.1)
    with pytest.raises(ValueError):
        clock.set(0.5)
