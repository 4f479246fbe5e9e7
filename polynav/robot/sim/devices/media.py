"""Photos and videos from the on-board camera, saved in folders of the data directory.

A photo is one frame saved as ``<stamp>.png``; a video records frames at ``FRAME_RATE`` of the
runtime's clock for its duration and is saved as ``<stamp>.mkv`` (Motion-JPEG in Matroska,
:mod:`~polynav.robot.sim.devices.matroska`) when it ends or is stopped. The stamp is the
runtime's time in milliseconds when the capture started (moved on by a millisecond while a file
of that name exists, since simulated time restarts with each run), or a name the caller gives.
Names are one plain file-name component; files are written atomically.
"""

from __future__ import annotations

import itertools
import logging
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from polynav.errors import Conflict, InvalidRequest, NotFound, StorageError
from polynav.robot.devices import Camera, DeviceJob, JobState
from polynav.robot.sim.devices.camera import HEIGHT, WIDTH
from polynav.robot.sim.devices.matroska import mjpeg_mkv

log = logging.getLogger(__name__)

FRAME_RATE = 2.0  # [frames per simulated second]
MAX_DURATION = 600.0  # [s]


def check_name(name: str, what: str = "filename") -> str:
    """Raises: InvalidRequest: not a plain file name (no folders, no dot names)."""
    if (not isinstance(name, str) or not name or name.startswith(".") or "/" in name
            or "\\" in name or "\x00" in name or len(name) > 128):
        raise InvalidRequest(what, f"must be a plain file name, got {name!r}")
    return name


class MediaFolder:
    """The files of one kind (``ext``) in ``root``, by name without extension."""

    def __init__(self, root: Path, ext: str) -> None:
        self.root = root
        self.ext = ext

    def names(self) -> list[str]:
        """Oldest first."""
        if not self.root.is_dir():
            return []
        files = [p for p in self.root.iterdir() if p.is_file() and p.suffix == self.ext]
        return [p.stem for p in sorted(files, key=lambda p: (p.stat().st_mtime_ns, p.name))]

    def path(self, name: str) -> Path:
        """Raises: NotFound: no such file. InvalidRequest: a bad name."""
        path = self.root / (check_name(name, "file_timestamp") + self.ext)
        if not path.is_file():
            raise NotFound("file", name)
        return path

    def delete(self, name: str) -> None:
        self.path(name).unlink()

    def new_name(self, now: float, name: str | None) -> str:
        if name is not None:
            stem = check_name(name[: -len(self.ext)] if name.endswith(self.ext) else name)
            return stem
        for stamp in itertools.count(int(round(now * 1000.0))):
            if not (self.root / f"{stamp}{self.ext}").exists():
                return str(stamp)
        raise AssertionError("unreachable")

    def write(self, name: str, data: bytes) -> Path:
        self.root.mkdir(parents=True, exist_ok=True)
        path = self.root / (name + self.ext)
        fd, tmp = tempfile.mkstemp(prefix=f".{name}.", dir=self.root)
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(data)
                f.flush()
                os.fsync(f.fileno())
            os.replace(tmp, path)
        except OSError as exc:
            Path(tmp).unlink(missing_ok=True)
            raise StorageError(f"{path}: {exc}") from exc
        return path


@dataclass(slots=True)
class _Recording:
    job: DeviceJob
    name: str
    view: str
    duration: float
    frames: list[tuple[int, bytes]] = field(default_factory=list)
    next_frame: float = 0.0


class VideoRecorder:
    """Records one video at a time from ``camera`` into ``folder``."""

    def __init__(self, camera: Camera, folder: MediaFolder) -> None:
        self._camera = camera
        self.folder = folder
        self._recording: _Recording | None = None
        self._jobs: dict[str, DeviceJob] = {}
        self._ids = itertools.count(1)
        self.saved: dict[str, str] = {}  # job id -> file name of the video it saved

    def start(self, now: float, *, view: str, duration: float, name: str | None) -> DeviceJob:
        """Raises: InvalidRequest: a duration outside (0, MAX_DURATION], a bad name or view.
        Conflict: a recording runs."""
        if not 0.0 < duration <= MAX_DURATION:
            raise InvalidRequest("duration", f"must be in (0, {MAX_DURATION:g}] s, got "
                                             f"{duration!r}")
        if self._recording is not None:
            raise Conflict("a video is being recorded; stop it first")
        self._camera.capture(now, view=view, fmt="jpeg")  # checks the view before starting
        stem = self.folder.new_name(now, name)
        job = DeviceJob(f"video-{next(self._ids)}", "video", JobState.WORKING, 0.0, now)
        self._recording = _Recording(job, stem, view, duration, next_frame=now)
        self._jobs[job.job_id] = job
        log.info("recording video %s for %gs", stem, duration)
        self.tick(now)
        return job

    def job(self, job_id: str) -> DeviceJob | None:
        return self._jobs.get(job_id)

    @property
    def recording(self) -> bool:
        return self._recording is not None

    @property
    def current_name(self) -> str | None:
        """The file name (without extension) of the video being recorded."""
        return self._recording.name if self._recording is not None else None

    def tick(self, now: float) -> None:
        rec = self._recording
        if rec is None:
            return
        started = rec.job.started
        end = started + rec.duration
        while rec.next_frame <= min(now, end) + 1e-9 and rec.next_frame < end - 1e-9:
            stamp_ms = int(round((rec.next_frame - started) * 1000.0))
            rec.frames.append((stamp_ms, self._camera.capture(rec.next_frame, view=rec.view,
                                                              fmt="jpeg")))
            rec.next_frame += 1.0 / FRAME_RATE
        if now >= end - 1e-9:
            self._finish(JobState.COMPLETE, 1.0)
        else:
            progress = round((now - started) / rec.duration, 6)
            self._set(rec, JobState.WORKING, progress)

    def stop(self, now: float) -> bool:
        """Stop recording and save what was recorded; whether a recording ran."""
        if self._recording is None:
            return False
        self.tick(now)
        if self._recording is not None:
            self._finish(JobState.CANCELLED, self._recording.job.progress)
        return True

    def _finish(self, state: JobState, progress: float) -> None:
        rec = self._recording
        assert rec is not None
        self._recording = None
        self.folder.write(rec.name, mjpeg_mkv(rec.frames, WIDTH, HEIGHT))
        self.saved[rec.job.job_id] = rec.name
        self._set(rec, state, progress)
        log.info("video %s saved: %d frames", rec.name, len(rec.frames))

    def _set(self, rec: _Recording, state: JobState, progress: float) -> None:
        job = rec.job
        rec.job = DeviceJob(job.job_id, job.kind, state, progress, job.started)
        self._jobs[job.job_id] = rec.job
