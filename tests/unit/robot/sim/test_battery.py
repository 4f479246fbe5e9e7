from __future__ import annotations

import numpy as np
import pytest

from polynav.robot.sim.battery import _SHARE, _SOC, Battery, _share, open_circuit_voltage
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


def test_charging_is_constant_current_then_tapers_at_the_full_voltage() -> None:
    battery = Battery(SimConfig(battery_start_percent=20.0, battery_charge_rate=40.0))
    _run(battery, 450.0, 0.0, charging=True)
    assert battery.state.percent == pytest.approx(25.0)  # constant current: 8 A into 20 Ah
    assert battery.state.current == pytest.approx(8.0)
    assert battery.state.charging and battery.state.voltage < 29.4
    currents = []
    while battery.state.percent < 99.9:
        _run(battery, 60.0, 0.0, charging=True)
        currents.append(battery.state.current)
    tail = [i for i in currents if i < 8.0 - 1e-9]
    assert tail and tail == sorted(tail, reverse=True)  # the charger holds the voltage
    assert battery.state.voltage == pytest.approx(29.4)
    _run(battery, 3600.0, 0.0, charging=True)
    assert battery.state.percent == 100.0 and battery.state.current == 0.0


def test_charging_from_20_to_95_percent_takes_about_two_hours() -> None:
    battery = Battery(SimConfig(battery_start_percent=20.0, battery_charge_rate=40.0))
    seconds = 0.0
    while battery.state.percent < 95.0:
        _run(battery, 60.0, 0.0, charging=True)
        seconds += 60.0
    assert 1.9 * 3600 < seconds < 2.6 * 3600


def test_the_voltage_follows_a_lithium_curve_and_sags_under_load() -> None:
    assert open_circuit_voltage(0.0, 22.0, 29.4) == pytest.approx(22.0)
    assert open_circuit_voltage(100.0, 22.0, 29.4) == pytest.approx(29.4)
    middle = [open_circuit_voltage(p, 22.0, 29.4) for p in (30.0, 50.0, 70.0)]
    assert middle[2] - middle[0] < 0.3 * 7.4  # flat in the middle
    assert open_circuit_voltage(10.0, 22.0, 29.4) - 22.0 > 0.3 * 7.4  # steep at the ends
    idle, moving = Battery(SimConfig()), Battery(SimConfig())
    _run(idle, 1.0, 0.0)
    _run(moving, 1.0, 1.0)
    rest = open_circuit_voltage(idle.state.percent, 22.0, 29.4)
    assert moving.state.voltage < idle.state.voltage < rest


def test_charge_never_goes_below_empty() -> None:
    battery = Battery(SimConfig(battery_start_percent=0.1))
    _run(battery, 600.0, 1.0)
    assert battery.state.percent == 0.0
    assert battery.state.voltage < 22.0  # empty, and still loaded


def test_the_open_circuit_curve_matches_numpys_interp_bit_for_bit() -> None:
    """The plain-Python interpolation stands in for ``np.interp`` every physics step: the same
    bits at the knots, just beside them, outside the curve and across it."""
    rng = np.random.default_rng(7)
    values = np.concatenate((
        _SOC, np.nextafter(_SOC, 200.0), np.nextafter(_SOC, -200.0),
        rng.uniform(-5.0, 105.0, 20_000), [-0.0, 1e-300, 100.0 - 1e-13],
    ))
    expected = np.interp(values, _SOC, _SHARE)
    got = np.array([_share(v) for v in values.tolist()])
    assert np.array_equal(got, expected)
    assert open_circuit_voltage(57.3, 21.0, 29.4) == float(
        21.0 + (29.4 - 21.0) * np.interp(57.3, _SOC, _SHARE))
