"""The peripherals through the runtime, on simulated time (runtime.peripherals)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav.errors import Conflict, InvalidRequest
from polynav.geometry import Pose2D
from polynav.robot.devices import AxisMode, CalibrationStatus, JobState
from polynav.robot.sim.devices.speaker import speech_duration
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from tests.unit.robot.sim.ascii_world import ascii_world

ROOM = "\n".join(["#" * 80] + ["#" + "." * 78 + "#"] * 78 + ["#" * 80])


@pytest.fixture
def runtime(tmp_path: Path) -> Iterator[RobotRuntime]:
    world = ascii_world(ROOM, start=Pose2D(4.0, 2.0, 0.0))
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        yield RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False))


def test_speech_plays_for_its_duration_on_simulated_time(runtime: RobotRuntime) -> None:
    p = runtime.peripherals
    duration = p.say("欢迎光临")
    assert duration == speech_duration("欢迎光临")
    assert p.speaking()
    runtime.advance(duration - 0.1)
    assert p.speaking()
    runtime.advance(0.2)
    assert not p.speaking()
    packages, records, current = p.voice_records()
    assert (packages, current) == (["default"], "default")
    assert records[0].text == "欢迎光临" and records[0].active_count == 1
    assert (p.data_dir / "voice" / "packages" / "default").is_dir()  # type: ignore[operator]


def test_the_slide_moves_on_the_clock_through_the_runtime(runtime: RobotRuntime) -> None:
    p = runtime.peripherals
    job = p.move_axis("slide", AxisMode.RATIO, target=0.5, speed=0.1)
    assert p.job(job.job_id).state is JobState.WORKING  # type: ignore[union-attr]
    runtime.advance(12.0)  # 0.17 m home at 0.03 m/s, then 0.3 m at 0.1 m/s
    state = p.axis_state("slide")
    assert state.homed and state.ratio == pytest.approx(0.5)
    assert p.job(job.job_id).state is JobState.COMPLETE  # type: ignore[union-attr]


def test_all_or_none_of_several_outputs_are_set(runtime: RobotRuntime) -> None:
    p = runtime.peripherals
    p.set_outputs("voice_io", {0: 1, 1: 1})
    with pytest.raises(InvalidRequest):
        p.set_outputs("voice_io", {2: 1, 5: 1})
    assert p.io_state("voice_io") == ([1, 1, None, None], [0, 0, 0, 0])


def test_camera_calibration_finishes_when_the_robot_is_driven_round_a_loop(
    runtime: RobotRuntime,
) -> None:
    p = runtime.peripherals
    p.start_calibration("camera")
    # Teleop a circle of radius 0.75 m (4.7 m round) and a little more.
    for _ in range(70):
        runtime.teleop(0.3, 0.4)
        runtime.advance(0.25)
    assert p.calibration("camera")[0] is CalibrationStatus.CALIBRATED
    p.complete_calibration("camera")
    p.start_calibration("lidar")
    assert p.calibration("lidar")[0] is CalibrationStatus.CALIBRATING


def test_calibration_is_refused_while_navigating(runtime: RobotRuntime) -> None:
    runtime.start_navigation("ground")
    with pytest.raises(Conflict, match="navigating"):
        runtime.peripherals.start_calibration("camera")


def test_a_photo_and_a_video_land_in_the_data_directory(runtime: RobotRuntime) -> None:
    p = runtime.peripherals
    name = p.take_photo("front", None)
    assert p.photos.path(name).read_bytes()[:4] == b"\x89PNG"
    job, stem = p.start_video("front", 2.0, None)
    runtime.advance(2.1)
    assert p.job(job.job_id).state is JobState.COMPLETE  # type: ignore[union-attr]
    assert p.videos.names() == [p.recorder.saved[job.job_id]] == [stem]
    snapshot = p.ptz_snapshot()
    assert snapshot.suffix == ".jpg" and snapshot.parent == p.photos.root


def test_the_event_log_covers_events_from_before_anyone_read_it(runtime: RobotRuntime) -> None:
    runtime.start_navigation("ground")
    runtime.advance(0.1)
    text = runtime.peripherals.event_log.text()
    assert "mode_changed" in text and '"new": "navigating"' in text
    assert text.splitlines()[0].startswith("[")
