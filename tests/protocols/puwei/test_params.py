"""Navigation parameters (puwei-api §7) on the runtime settings, units converted."""

from __future__ import annotations

import math

import pytest

from tests.protocols.puwei.conftest import Harness, refused

COVERED = {
    "GET /api/param/get/:name": "test_get_reads_each_parameter_in_puweis_unit",
    "GET /api/param/set/:name/:value": "test_set_changes_the_runtime_setting",
}


def test_get_reads_each_parameter_in_puweis_unit(puwei: Harness) -> None:
    s = puwei.runtime.settings()
    assert puwei.ok("/api/param/get/max_vel") == pytest.approx(s.max_linear_velocity)
    assert puwei.ok("/api/param/get/pos_err") == pytest.approx(s.xy_goal_tolerance)
    assert puwei.ok("/api/param/get/ang_err") == pytest.approx(
        math.degrees(s.yaw_goal_tolerance), abs=1e-5)
    assert puwei.ok("/api/param/get/low_bat") == pytest.approx(s.low_battery_percent)
    assert puwei.ok("/api/param/get/full_bat") == pytest.approx(s.full_battery_percent)
    assert isinstance(puwei.ok("/api/param/get/max_vel"), float)


@pytest.mark.parametrize(("name", "value", "setting", "inside"), [
    ("max_vel", "0.35", "max_linear_velocity", 0.35),
    ("pos_err", "0.2", "xy_goal_tolerance", 0.2),
    ("ang_err", "10", "yaw_goal_tolerance", math.radians(10)),
    ("low_bat", "30", "low_battery_percent", 30.0),
    ("full_bat", "90", "full_battery_percent", 90.0),
])
def test_set_changes_the_runtime_setting(puwei: Harness, name: str, value: str, setting: str,
                                         inside: float) -> None:
    assert puwei.ok(f"/api/param/set/{name}/{value}") is None
    assert getattr(puwei.runtime.settings(), setting) == pytest.approx(inside)
    assert puwei.ok(f"/api/param/get/{name}") == pytest.approx(float(value))


def test_bad_names_and_values_are_refused_and_change_nothing(puwei: Harness) -> None:
    before = puwei.runtime.settings()
    cases = {
        "/api/param/set/max_vel/0.9": 2,  # above the document's 0.8
        "/api/param/set/max_vel/0.05": 2,
        "/api/param/set/pos_err/1.5": 2,
        "/api/param/set/pos_err/0.5": 2,  # in the document's range, beyond the runtime's
        "/api/param/set/ang_err/1": 2,
        "/api/param/set/ang_err/181": 2,
        "/api/param/set/low_bat/5": 2,
        "/api/param/set/full_bat/101": 2,
        "/api/param/set/max_vel/fast": 2,
        "/api/param/set/max_vel/nan": 2,
        "/api/param/set/max_vel/inf": 2,
        "/api/param/set/speed/0.5": 3,
        "/api/param/get/speed": 3,
    }
    for path, code in cases.items():
        body = refused(puwei.get(path))
        assert body["code"] == code, (path, body)
    assert puwei.runtime.settings() == before
