"""Saving a map as a job: the slow part of a stop or a save, off the runtime's loop thread.

Finishing a map (the last optimisation of the whole pose graph, then rendering every scan) and
writing its files took 11 s on the demo floor; done between ticks, as a command, it held the
control loop (and the HTTP request) that long. A *job* splits it: the runtime checks and
takes what it needs between ticks, a worker thread does the heavy part, and the result is
applied between ticks again. :class:`MappingJobs` is the runtime's book of those jobs: at most
one saving at a time, the last :data:`KEPT` remembered for ``GET /api/mapping/jobs/{id}``. It
is read from any thread (the API's) and written by the loop and the worker, under its lock.
"""

from __future__ import annotations

import enum
import logging
import threading
from collections import OrderedDict
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from polynav.errors import Conflict, NotFound

if TYPE_CHECKING:
    from polynav.runtime.mapping_status import MappingStatus

log = logging.getLogger(__name__)

KEPT = 32
"""Finished jobs remembered (older ones are forgotten: 404)."""


class JobState(enum.Enum):
    SAVING = "saving"
    SAVED = "saved"
    FAILED = "failed"


class JobKind(enum.Enum):
    STOP = "stop"
    """Finish the map, save it, and end mapping (the robot is BUSY meanwhile)."""
    SAVE = "save"
    """Save the map so far; mapping goes on."""


@dataclass(frozen=True, slots=True)
class MappingJob:
    """One save of the map being built, on the runtime's clock [s].

    Attributes:
        id: the job's id (``"1"``, ``"2"``, ... for the runtime's lifetime).
        name: the map's name it saves under.
        kind: a stop (finish and end mapping) or a save (mapping goes on).
        state: ``saving``, then ``saved`` or ``failed``.
        started_at, finished_at: when it began and ended (``None`` while saving).
        error: why it failed (the disk, the store), ``None`` otherwise.
    """

    id: str
    name: str
    kind: JobKind
    state: JobState
    started_at: float
    finished_at: float | None = None
    error: str | None = None

    @property
    def done(self) -> bool:
        return self.state is not JobState.SAVING

    def to_dict(self) -> dict[str, object]:
        """The job as ``GET /api/mapping/jobs/{id}`` and the status show it (JSON-ready)."""
        return {
            "id": self.id,
            "name": self.name,
            "kind": self.kind.value,
            "state": self.state.value,
            "error": self.error,
            "started_at": float(self.started_at),
            "finished_at": None if self.finished_at is None else float(self.finished_at),
        }


class MappingJobs:
    """The runtime's mapping jobs: the one saving (if any) and the last ones finished."""

    def __init__(self, kept: int = KEPT) -> None:
        self._lock = threading.Lock()
        self._jobs: OrderedDict[str, MappingJob] = OrderedDict()
        self._kept = kept
        self._count = 0
        self._running: str | None = None
        self._session: str | None = None  # the last job of the current mapping session
        self.finishing: MappingStatus | None = None
        """The session a stop job finishes, as it was when the job began (the status shows it
        while the robot is BUSY); ``None`` otherwise. Read and written between ticks."""

    def begin(self, kind: JobKind, name: str, now: float) -> MappingJob:
        """A new job, saving from ``now``; it is the session's job from now on.

        Raises:
            Conflict: another job is saving (one at a time: they would race for the files).
        """
        with self._lock:
            running = self._jobs.get(self._running) if self._running is not None else None
            if running is not None:
                raise Conflict(f"map {running.name!r} is being saved (job {running.id}): wait "
                               "for it to finish")
            self._count += 1
            job = MappingJob(str(self._count), name, kind, JobState.SAVING, now)
            self._jobs[job.id] = job
            self._running = self._session = job.id
            while len(self._jobs) > self._kept:
                self._jobs.popitem(last=False)
            return job

    def end(self, job_id: str, now: float, error: str | None = None) -> MappingJob:
        """Mark the job ``saved`` (no ``error``) or ``failed``; returns it as it ends."""
        with self._lock:
            job = replace(self._jobs[job_id], finished_at=now, error=error,
                          state=JobState.SAVED if error is None else JobState.FAILED)
            self._jobs[job_id] = job
            if self._running == job_id:
                self._running = None
        log.log(logging.INFO if error is None else logging.ERROR,
                "mapping job %s (%s %r) %s%s", job.id, job.kind.value, job.name,
                job.state.value, "" if error is None else f": {error}")
        return job

    def get(self, job_id: str) -> MappingJob:
        """The job of that id.

        Raises:
            NotFound: no such job (or forgotten: only the last :data:`KEPT` are kept).
        """
        with self._lock:
            job = self._jobs.get(job_id)
        if job is None:
            raise NotFound("mapping job", job_id)
        return job

    @property
    def running(self) -> MappingJob | None:
        """The job saving now, if any."""
        with self._lock:
            return None if self._running is None else self._jobs.get(self._running)

    def session_job(self) -> MappingJob | None:
        """The current mapping session's last job (saving or ended), if it had one."""
        with self._lock:
            return None if self._session is None else self._jobs.get(self._session)

    def new_session(self) -> None:
        """A mapping session starts: it has no job yet."""
        with self._lock:
            self._session = None
