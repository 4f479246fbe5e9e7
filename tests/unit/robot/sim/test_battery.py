from __future__ import annotations

import pytest

from polynav.robot.sim.battery import Battery
from polynav.robot.sim.config import SimConfig


def _run(battery: Battery, seconds: float, speed: float, *, charging: bool = False) -> None:
    for k in range(round(seconds / 0.02)):
        battery.update(0.02, speed * 0.02, charging=charging, stamp=(k + 1) * 0.02)


def test_idle_drain_per_hour() -> None:
    battery = Battery(SimConfig(battery_idle_drain=3.0, battery_start_percent=80.0))
    _run(battery, 3600.0, 0.0)
    assert battery.state.percent == pytest.approx(77.0)
    assert battery.state.current == pytest.approx(-20.0 * 3.0 / 100.0)
    assert not battery.state.charging


def test_battery_drains_faster_when_moving() -> None:
    idle, moving = Battery(SimConfig()), Battery(SimConfig())
    _run(idle, 600.0, 0.0)
    _run(moving, 600.0, 1.0)
    drained_idle = 80.0 - idle.state.percent
    drained_moving = 80.0 - moving.state.percent
    # 600 m at 0.005 %/m adds 3 % to the 0.5 % of ten idle minutes.
    assert drained_idle == pytest.approx(0.5)
    assert drained_moving == pytest.approx(3.5)
    assert moving.state.current < idle.state.current < 0.0
    assert moving.state.voltage < idle.state.voltage


def test_charging_fills_up_to_full_and_reports_it() -> None:
    battery = Battery(SimConfig(battery_start_percent=90.0, battery_charge_rate=40.0))
    _run(battery, 450.0, 0.0, charging=True)
    assert battery.state.percent == pytest.approx(95.0)
    assert battery.state.charging and battery.state.current > 0.0
    _run(battery, 3600.0, 0.0, charging=True)
    assert battery.state.percent == 100.0
    assert battery.state.voltage == pytest.approx(29.4)


def test_charge_never_goes_below_empty() -> None:
    battery = Battery(SimConfig(battery_start_percent=0.1))
    _run(battery, 600.0, 1.0)
    assert battery.state.percent == 0.0
    assert battery.state.voltage == pytest.approx(22.0)
