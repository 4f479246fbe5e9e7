from __future__ import annotations

import numpy as np
import pytest

from polynav.robot.sim.devices.environment import QUANTITIES, SimEnvironmentSensors


def test_readings_drift_on_the_clock_and_hold_between_steps() -> None:
    sensors = SimEnvironmentSensors(seed=1)
    first = sensors.read_env(0.0)
    assert sensors.read_env(0.5) == first  # no step yet: the same reading
    later = sensors.read_env(30.0)
    assert later.stamp == 30.0
    assert later != first
    assert later.noise != first.noise  # the fastest quantity moved


def test_a_reading_at_a_time_is_the_same_for_a_seed_however_often_it_is_read() -> None:
    a, b = SimEnvironmentSensors(seed=7), SimEnvironmentSensors(seed=7)
    for t in range(100):
        a.read_env(float(t))
    assert a.read_env(100.0) == b.read_env(100.0)
    assert a.read_air(100.0) == b.read_air(100.0)
    assert SimEnvironmentSensors(seed=8).read_env(100.0) != b.read_env(100.0)


def test_values_stay_plausible_over_a_day_and_wander_around_their_means() -> None:
    sensors = SimEnvironmentSensors(seed=3)
    temps, co2, pm = [], [], []
    for t in range(0, 86_400, 60):
        env, air = sensors.read_env(float(t)), sensors.read_air(float(t))
        assert env.pm1_0 <= env.pm2_5 <= env.pm10
        assert min(env.smoke, env.lel, env.pm1_0, air.co2, air.illuminance) >= 0.0
        assert 0.0 <= air.humidity <= 100.0
        assert abs(air.temperature - env.temperature) < 2.0  # the same room
        temps.append(env.temperature)
        co2.append(air.co2)
        pm.append(env.pm2_5)
    assert np.mean(temps) == pytest.approx(QUANTITIES["temperature"].mean, abs=0.5)
    assert np.mean(co2) == pytest.approx(QUANTITIES["co2"].mean, abs=40.0)
    assert np.std(temps) > 0.2  # it does drift
