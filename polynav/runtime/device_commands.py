"""The robot's peripherals as runtime commands: speech, IO, sensors, slide and jacking,
calibration, software update, photos, videos and the network camera.

:class:`Peripherals` is a runtime service (``runtime.peripherals``). It wraps the backend's
:class:`~polynav.robot.devices.DeviceSet` (the simulator's by default) and the storage every
backend needs alike, in the robot's data directory: voice packages (``voice/``), photos and
camera snapshots (``media/photos/``) and videos (``media/videos/``). Every command runs between
ticks with the runtime's ``now`` (the loop thread is the only writer, DESIGN §1), and the
runtime ticks the service every control period so the calibrations see the robot move and a
video records its frames on simulated time. Adapters translate; the behaviour is here and in
the devices.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, TypeVar

from polynav.errors import Conflict, InvalidRequest
from polynav.robot.devices import (
    AirReading,
    Axis,
    AxisMode,
    AxisState,
    Calibration,
    CalibrationStatus,
    DeviceJob,
    DeviceSet,
    EnvReading,
    IoPorts,
    JobState,
    PtzPose,
)
from polynav.robot.sim.devices.media import MediaFolder, VideoRecorder
from polynav.robot.sim.devices.speaker import speech_duration
from polynav.robot.sim.devices.voice_library import VoiceLibrary, VoiceRecord
from polynav.runtime.event_log import EventLog

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

T = TypeVar("T")

AXES = ("slide", "jacking", "jacking_rotation")
MAX_JOBS = 512  # finished device jobs remembered, newest kept
GREETING = "欢迎光临"  # "welcome": what greeting mode says (its audio can be replaced)
GREETING_RANGE = 2.0  # [m] a person this near is greeted

IO_BANKS = ("io", "expansion_io", "voice_io")
CAMERA_VIEWS = ("front", "back")


class Peripherals:
    """The peripheral commands of one runtime.

    Args:
        runtime: the robot.
        devices: its peripherals.
        data_dir: where voice packages, photos and videos are kept; without one those
            commands are refused.
    """

    def __init__(self, runtime: RobotRuntime, devices: DeviceSet, data_dir: Path | None) -> None:
        self._runtime = runtime
        self.devices = devices
        self.data_dir = data_dir
        root = data_dir if data_dir is not None else Path("/nonexistent")
        self.voice = VoiceLibrary(root / "voice")
        self.photos = MediaFolder(root / "media" / "photos", ".png")
        self.snapshots = MediaFolder(root / "media" / "photos", ".jpg")
        self.videos = MediaFolder(root / "media" / "videos", ".mkv")
        self.recorder = VideoRecorder(devices.camera, self.videos)
        self.greeting = False
        self._greeted: set[int] = set()
        self.event_log = EventLog(runtime.bus)
        # Jobs as of the last tick, readable from any thread without waiting for the loop
        # (adapters poll them in tight loops); running ones are refreshed every tick.
        self._jobs: dict[str, DeviceJob] = {}
        self._running: dict[str, Callable[[float], DeviceJob | None]] = {}
        self._jobs_lock = threading.Lock()

    def tick(self, now: float) -> None:
        """One control period (called by the runtime's loop)."""
        robot = self._runtime.robot
        self.devices.observe(now, robot.read_odometry(), robot.read_scan())
        self.recorder.tick(now)
        if self.greeting:
            self._greet(now)
        self._refresh_jobs(now)

    def job(self, job_id: str) -> DeviceJob | None:
        """A device job as of the last tick (or its start), from any thread, without waiting.
        """
        with self._jobs_lock:
            return self._jobs.get(job_id)

    def _watch(self, job: DeviceJob, read: Callable[[float], DeviceJob | None]) -> DeviceJob:
        with self._jobs_lock:
            self._jobs[job.job_id] = job
            self._running[job.job_id] = read
            while len(self._jobs) > MAX_JOBS:
                del self._jobs[next(iter(self._jobs))]
        return job

    def _refresh_jobs(self, now: float) -> None:
        with self._jobs_lock:
            for job_id, read in list(self._running.items()):
                job = read(now)
                if job is None:
                    del self._running[job_id]
                    continue
                self._jobs[job_id] = job
                if job.state is not JobState.WORKING:
                    del self._running[job_id]

    def set_greeting(self, on: bool) -> None:
        """Greeting mode: say :data:`GREETING` to each person who comes within
        :data:`GREETING_RANGE` (once per person while they stay in view).

        Raises:
            Conflict: no data directory (the greeting's audio lives there).
        """
        self._files()

        def run(now: float) -> None:
            self.greeting = on
            self._greeted.clear()

        self._run(run)

    def _greet(self, now: float) -> None:
        people = self._runtime.robot.read_people()
        in_view = {p.track_id for p in people}
        self._greeted &= in_view  # someone who left and comes back is greeted again
        near = [p.track_id for p in people
                if p.track_id not in self._greeted and math.hypot(p.x, p.y) <= GREETING_RANGE]
        if near and not self.devices.speaker.playing(now):
            self._greeted.update(near)
            self.voice.play(GREETING, int(round(now * 1000.0)))
            self.devices.speaker.say(now, GREETING, speech_duration(GREETING))
            log.info("greeting %d people at t=%.2f", len(near), now)

    def _run(self, fn: Callable[[float], T]) -> T:
        runtime = self._runtime
        return runtime.run_between_ticks(lambda: fn(runtime.now()))

    def _files(self) -> None:
        if self.data_dir is None:
            raise Conflict("this robot has no data directory for files")

    # -- speech ----------------------------------------------------------------------------

    def say(self, text: str) -> float:
        """Speak ``text`` from the current voice package (its audio made the first time);
        returns how long it plays [s].

        Raises:
            InvalidRequest: an empty text. Conflict: no data directory.
        """
        self._files()

        def run(now: float) -> float:
            self.voice.play(text, int(round(now * 1000.0)))
            duration = speech_duration(text)
            self.devices.speaker.say(now, text, duration)
            log.info("saying %r for %.2fs", text, duration)
            return duration

        return self._run(run)

    def speaking(self) -> bool:
        return self._run(self.devices.speaker.playing)

    def stop_speaking(self) -> bool:
        return self._run(self.devices.speaker.stop)

    @property
    def volume(self) -> int:
        return self.devices.speaker.volume

    def set_volume(self, percent: int) -> None:
        """Raises: InvalidRequest: not 0..100."""
        self._run(lambda now: self.devices.speaker.set_volume(percent))

    def voice_records(self) -> tuple[list[str], list[VoiceRecord], str]:
        """(packages, records, current package)."""
        self._files()
        return self._run(lambda now: (self.voice.packages(), self.voice.records(),
                                      self.voice.current))

    def voice_library(self, fn: Callable[[VoiceLibrary], T]) -> T:
        """Run ``fn`` on the voice library between ticks (imports, exports, aliases).

        Raises:
            Conflict: no data directory; whatever ``fn`` raises.
        """
        self._files()
        return self._run(lambda now: fn(self.voice))

    # -- IO and sensors --------------------------------------------------------------------

    def io_bank(self, name: str) -> IoPorts:
        if name not in IO_BANKS:
            raise KeyError(name)
        bank: IoPorts = getattr(self.devices, name)
        return bank

    def io_state(self, name: str) -> tuple[list[int | None], list[int]]:
        """(outputs, inputs) of bank ``name`` (``io``, ``expansion_io``, ``voice_io``)."""
        bank = self.io_bank(name)
        return self._run(lambda now: (list(bank.outputs()), list(bank.inputs())))

    @property
    def buzzer_on(self) -> bool:
        return self.devices.buzzer.on

    def set_buzzer(self, on: bool) -> None:
        """Sound the chassis buzzer, or silence it."""
        buzzer = self.devices.buzzer
        self._run(lambda now: buzzer.set(now, on))

    def set_outputs(self, name: str, levels: Mapping[int, int]) -> None:
        """Set several outputs of one bank at once: all or none.

        Raises:
            InvalidRequest: a port or level the bank has not (nothing is changed).
        """
        bank = self.io_bank(name)

        def run(now: float) -> None:
            for port, level in levels.items():  # check every one before changing any
                if port not in bank.output_ports:
                    raise InvalidRequest("port", f"outputs are {bank.output_ports.start}.."
                                                 f"{bank.output_ports.stop - 1}, not {port!r}")
                if level not in (0, 1):
                    raise InvalidRequest("level", f"must be 0 or 1, got {level!r}")
            for port, level in levels.items():
                bank.set_output(port, level)

        self._run(run)

    def set_pwm(self, name: str, port: int, frequency: int, duty: int) -> None:
        bank = self.io_bank(name)
        self._run(lambda now: bank.set_pwm(port, frequency, duty))

    def set_servo(self, name: str, port: int, angle: int) -> None:
        bank = self.io_bank(name)
        self._run(lambda now: bank.set_servo(port, angle))

    def environment(self) -> tuple[EnvReading, AirReading]:
        """The environment and air sensors now."""
        sensors = self.devices.sensors
        return self._run(lambda now: (sensors.read_env(now), sensors.read_air(now)))

    # -- slide and jacking -----------------------------------------------------------------

    def axis(self, name: str) -> Axis:
        if name not in AXES:
            raise KeyError(name)
        axis: Axis = getattr(self.devices, name)
        return axis

    def axis_state(self, name: str) -> AxisState:
        axis = self.axis(name)
        return self._run(axis.state)

    def move_axis(
        self, name: str, mode: AxisMode, *, target: float = 0.0, speed: float = 0.0,
        duration: float = 0.0,
    ) -> DeviceJob:
        """Raises: InvalidRequest: see :meth:`~polynav.robot.devices.Axis.move`."""
        axis = self.axis(name)

        def run(now: float) -> DeviceJob:
            job = axis.move(now, mode, target=target, speed=speed, duration=duration)
            self._refresh_jobs(now)  # the move it replaced ends CANCELLED
            return self._watch(job, lambda t: axis.job(t, job.job_id))

        return self._run(run)

    def stop_axis(self, name: str) -> None:
        axis = self.axis(name)

        def run(now: float) -> None:
            axis.stop(now)
            self._refresh_jobs(now)

        self._run(run)

    # -- calibration -----------------------------------------------------------------------

    def calibration(self, which: str) -> tuple[CalibrationStatus, float]:
        """(status, accuracy) of ``camera`` or ``lidar`` calibration."""
        cal = self._calibration(which)
        return self._run(lambda now: (cal.status(), cal.accuracy))

    def start_calibration(self, which: str) -> None:
        """Raises: Conflict: already running, or (lidar) the camera is not calibrated;
        navigation or mapping runs (the robot must be driven by hand)."""
        cal = self._calibration(which)

        def run(now: float) -> None:
            mode = self._runtime.mode.value
            if mode in ("navigating", "mapping", "busy"):
                raise Conflict(f"the robot is {mode}: stop it before calibrating")
            cal.start(now)

        self._run(run)

    def cancel_calibration(self, which: str) -> bool:
        cal = self._calibration(which)
        return self._run(lambda now: cal.cancel())

    def complete_calibration(self, which: str) -> None:
        """Raises: Conflict: not CALIBRATED."""
        cal = self._calibration(which)
        self._run(lambda now: cal.complete())

    def calibrate_imu(self) -> None:
        """Raises: Conflict: the robot moves or a calibration runs."""
        imu = self.devices.imu_calibration
        self._run(lambda now: imu.start(now, self._runtime.robot.read_odometry()))

    def _calibration(self, which: str) -> Calibration:
        if which == "camera":
            return self.devices.camera_calibration
        if which == "lidar":
            return self.devices.lidar_calibration
        raise KeyError(which)

    # -- camera, photos, videos ------------------------------------------------------------

    def take_photo(self, view: str, name: str | None) -> str:
        """Save a photo; returns its name (the stamp, or ``name``).

        Raises:
            InvalidRequest: unknown view, a bad name. Conflict: no data directory.
        """
        self._files()

        def run(now: float) -> str:
            data = self.devices.camera.capture(now, view=view, fmt="png")
            stem = self.photos.new_name(now, name)
            self.photos.write(stem, data)
            return stem

        return self._run(run)

    def start_video(self, view: str, duration: float, name: str | None) -> tuple[DeviceJob, str]:
        """Start recording; the job and the name the video will be saved under.

        Raises:
            InvalidRequest: bad duration, view or name. Conflict: a recording runs, or no
                data directory.
        """
        self._files()

        def run(now: float) -> tuple[DeviceJob, str]:
            job = self.recorder.start(now, view=view, duration=duration, name=name)
            self._watch(job, lambda t: self.recorder.job(job.job_id))
            return job, self.recorder.current_name or ""

        return self._run(run)

    def stop_video(self) -> bool:
        """Stop recording and save the file; whether a recording ran."""

        def run(now: float) -> bool:
            stopped = self.recorder.stop(now)
            self._refresh_jobs(now)
            return stopped

        return self._run(run)

    def ptz(self, fn: Callable[[float], T]) -> T:
        """Run ``fn(now)`` against the PTZ camera between ticks."""
        return self._run(fn)

    def ptz_pose(self) -> PtzPose:
        return self._run(self.devices.ptz_camera.pose)

    def ptz_snapshot(self) -> Path:
        """Save a snapshot of the network camera with the photos; returns its path."""
        self._files()

        def run(now: float) -> Path:
            data = self.devices.ptz_camera.snapshot(now)
            return self.snapshots.write(self.snapshots.new_name(now, None), data)

        return self._run(run)

