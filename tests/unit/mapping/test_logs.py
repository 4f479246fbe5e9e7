from __future__ import annotations

import gzip
import json
import math
from pathlib import Path

import numpy as np
import pytest

from polynav.mapping import logs
from polynav.mapping.errors import EmptyLogError, LogError

FLASER = ("FLASER 4 1.0 2.0 81.9 3.0 9.0 9.0 1.0 9.0 9.0 1.0 {t} pippo {t}")
CARMEN = "\n".join([
    "# a comment",
    "PARAM robot_frontlaser_offset 0.0 nohost 0",
    "ODOM 0.0 0.0 0.0 0 0 0 10.00 pippo 10.00",
    "ODOM 1.0 0.0 0.5 0 0 0 11.00 pippo 11.00",
    "ODOM 7.0 7.0 3.0 0 0 0 0 pippo 0",  # stamp 0: a corrected pose, dropped
    FLASER.format(t="10.50"),
    "ODOM 2.0 1.0 1.0 0 0 0 12.00 pippo 12.00",
    FLASER.format(t="11.750"),
    "NEFF 12.5",
])


def _write(path: Path, text: str, *, compress: bool = False) -> Path:
    if compress:
        with gzip.open(path, "wt") as f:
            f.write(text)
    else:
        path.write_text(text)
    return path


@pytest.mark.parametrize("compress", [False, True])
def test_carmen_scans_take_interpolated_raw_odometry_not_laser_poses(
    tmp_path: Path, compress: bool
) -> None:
    log = logs.read_log(_write(tmp_path / "a.log", CARMEN, compress=compress))
    assert log.source == "carmen" and log.skipped_lines == 0 and log.has_odometry
    assert [s.stamp_text for s in log.scans] == ["10.50", "11.750"]
    first, second = log.scans
    assert (first.odom.x, first.odom.y, first.odom.theta) == pytest.approx((0.5, 0.0, 0.25))
    assert (second.odom.x, second.odom.y, second.odom.theta) == pytest.approx((1.75, 0.75, 0.875))


def test_flaser_beams_span_minus_90_degrees_and_no_return_is_inf(tmp_path: Path) -> None:
    scan = logs.read_log(_write(tmp_path / "a.log", CARMEN)).scans[0]
    # 4 beams is neither 180 nor 360: both ends included, 60° apart.
    assert np.degrees(scan.angles).tolist() == pytest.approx([-90.0, -30.0, 30.0, 90.0])
    assert scan.ranges[:2].tolist() == [1.0, 2.0]
    assert math.isinf(scan.ranges[2]) and scan.ranges[3] == 3.0


def test_corrupt_and_truncated_lines_are_skipped_and_counted(tmp_path: Path) -> None:
    bad = ["FLASER 4 1.0 2.0 x 3.0 9 9 1 9 9 1 12.5 pippo 12.5", "ODOM 1.0 2.0", "FLASER 4 1.0"]
    text = "\n".join([CARMEN, *bad])
    log = logs.read_log(_write(tmp_path / "a.log", text))
    assert len(log.scans) == 2
    assert log.skipped_lines == 3


def test_robotlaser_and_rawlaser_lines_give_their_own_angles_and_mount(tmp_path: Path) -> None:
    robot = ("ROBOTLASER1 0 -1.0 2.0 1.0 5.0 0.1 0 3 1.0 6.0 2.0 0 "
             "1.1 2.0 0.0 1.0 2.0 0.0 0 0 0 0 0 5.25 host 5.25")
    raw = "RAWLASER1 0 -0.5 1.0 0.5 5.0 0.1 0 3 1.0 2.0 3.0 1 7 6.5 host 6.5"
    log = logs.read_log(_write(tmp_path / "a.log", robot + "\n" + raw + "\n"))
    assert not log.has_odometry
    a, b = log.scans
    assert a.angles.tolist() == pytest.approx([-1.0, 0.0, 1.0])
    assert math.isinf(a.ranges[1])
    assert (a.sensor_pose.x, a.sensor_pose.y) == pytest.approx((0.1, 0.0))
    assert b.stamp_text == "6.5" and b.angles.tolist() == pytest.approx([-0.5, 0.0, 0.5])


@pytest.mark.parametrize("text", ["", "# only a comment\nODOM 0 0 0 0 0 0 1 h 1\n"])
def test_a_log_without_scans_is_a_clear_error(tmp_path: Path, text: str) -> None:
    with pytest.raises(EmptyLogError):
        logs.read_log(_write(tmp_path / "a.log", text))


def test_a_missing_file_is_a_log_error(tmp_path: Path) -> None:
    with pytest.raises(LogError):
        logs.read_log(tmp_path / "missing.log")


def test_intel_json_keeps_keys_verbatim_and_sorts_them_numerically(tmp_path: Path) -> None:
    doc = {"map": {
        "976052900.500000": {"range": [1.0, 81.83], "x": 1.0, "y": 2.0, "theta": 0.5},
        "976052890.244111": {"range": [2.0, 3.0], "x": 0.0, "y": 0.0, "theta": 0.0},
        "976052895.000000": {"range": [2.0], "x": 0.0},  # corrupt: no y, theta
    }}
    log = logs.read_log(_write(tmp_path / "s.json", json.dumps(doc)))
    assert [s.stamp_text for s in log.scans] == ["976052890.244111", "976052900.500000"]
    assert log.skipped_lines == 1
    assert log.scans[1].odom.x == 1.0 and math.isinf(log.scans[1].ranges[1])
    assert np.degrees(log.scans[0].angles).tolist() == pytest.approx([-90.0, 0.0])


def test_mines_log_integrates_wheel_ticks(tmp_path: Path) -> None:
    ranges = " ".join(["1000"] * logs.MINES_BEAMS)
    filler = " ".join(["0"] * 20)
    # 2000 ticks = pi rad of wheel on both wheels: straight ahead, 0.077 m x (pi + pi) as
    # BreezySLAM counts it; then the right wheel alone turns 1000 ticks more.
    lines = [f"1000000 0 0 0 {filler} {ranges} 0", f"2000000 0 2000 2000 {filler} {ranges} 0",
             f"3000000 0 2000 3000 {filler} {ranges} 0"]
    log = logs.read_log(_write(tmp_path / "exp.dat", "\n".join(lines)))
    assert log.source == "mines"
    assert log.scans[1].odom.x == pytest.approx(2.0 * math.pi * 0.077)
    turn = 0.077 / 0.165 * (math.pi / 2.0)  # BreezySLAM: (r / half axle) x (right - left)
    assert log.scans[2].odom.theta == pytest.approx(turn)
    assert log.scans[1].stamp == pytest.approx(2.0)
    assert math.isinf(log.scans[0].ranges[0]) and log.scans[0].ranges[300] == 1.0


def test_flaser_with_180_beams_ends_at_plus_89_degrees() -> None:
    angles = np.degrees(logs.flaser_angles(180))
    assert (angles[0], angles[1], angles[-1]) == pytest.approx((-90.0, -89.0, 89.0))
