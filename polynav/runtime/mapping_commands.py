"""Mapping commands of the runtime: start a map, watch it grow, save it, stop, cancel.

A part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` by subject (it is one class
to its callers); what it shares with the others is declared in
:class:`~polynav.runtime.internals.RuntimeParts`. A new map is started from FREE, where the
robot stands (its pose is the new map's frame). An existing map is *updated* (extended) from
FREE, the robot's pose on it given or found by global relocalization, or from NAVIGATING on that
map, where the robot is tracked; the new map keeps the old one's frame, so its points, paths
and keepouts stay valid. The robot is driven by teleop, local moves or exploration meanwhile,
and :meth:`stop_mapping` saves before it stops, as the vendors document.

Saving is a job (:mod:`~polynav.runtime.mapping_jobs`): checked and begun between ticks, its
heavy part (a stop's last optimisation of the whole graph, rendering, writing the files) on
another thread, so that the control loop never waits for it; the outcome is applied between
ticks. The native API starts jobs and answers at once (:meth:`stop_mapping_job`); the dialects'
synchronous :meth:`stop_mapping` and :meth:`save_mapping` run the same job on their own thread.
"""

from __future__ import annotations

import abc
import logging
import threading
from dataclasses import dataclass

from polynav.errors import Conflict, InvalidRequest, NotFound, NotLocalized, PolynavError
from polynav.geometry import Pose2D
from polynav.localization.interface import LocalizationState
from polynav.mapping.relocalization import Relocalizer
from polynav.maps.map import Map
from polynav.runtime.config import Mode
from polynav.runtime.exploration import Exploration
from polynav.runtime.internals import RuntimeParts
from polynav.runtime.loop import CommandLoop
from polynav.runtime.mapping_jobs import JobKind, MappingJob
from polynav.runtime.mapping_session import MappingSession
from polynav.runtime.mapping_status import MappingStatus, mapping_status
from polynav.store.rows import check_name

log = logging.getLogger(__name__)


class MappingCommands(RuntimeParts):
    _loop: CommandLoop

    def start_mapping(self, map_name: str | None = None, *, point: str | None = None,
                      pose: Pose2D | None = None) -> None:
        """Start a new map where the robot stands (its pose now is the new map's frame), or
        update ``map_name``: extend it with what the robot sees from now on, in its frame.

        When updating, the robot's pose on the map is the named ``point``, else ``pose``, else
        the navigation estimate (when NAVIGATING on that map, tracked, no goal active; the map
        is unloaded), else found by global relocalization of the current scan. On the
        simulator a given pose far from the robot places it there, as for navigation.

        Raises:
            Conflict: not FREE (navigating: stop navigation first, unless updating the map
                navigated on; already mapping; busy); ``NotLocalized`` when the robot cannot
                be found on the map.
            NotFound: unknown map or point.
            InvalidRequest: a point or pose without a map; both; a map of no simulated floor,
                or with a rotated origin or cells of another size than the SLAM's.
        """
        if map_name is None:
            if point is not None or pose is not None:
                raise InvalidRequest("point", "a point or pose locates the robot on a map being "
                                     "updated: name the map")
            self._call(self._start_new_map)
            return
        start = self._map_start(map_name, point, pose)
        self._call(
            lambda: self._start_update(start.name, start.floor, start.grid, start.initial)
        )

    def _start_new_map(self) -> None:
        self._refuse_if_shutting_down("mapping")
        if self._mode is Mode.MAPPING:
            raise Conflict("already mapping: stop or cancel it first")
        if self._mode is not Mode.FREE:
            raise Conflict(f"mapping starts from free (mode {self._mode.value}): "
                           "stop navigation first")
        self._halt_motion()
        self._mapping = MappingSession(self._floor_now(), self._status_pose(),
                                       started_at=self.now())
        self._mapping_jobs.new_session()
        self._set_mode(Mode.MAPPING)
        log.info("mapping started on floor %s", self._mapping.floor)

    def _start_update(self, name: str, floor: str, grid: Map, initial: Pose2D | None) -> None:
        self._refuse_if_shutting_down("mapping")
        if self._mode is Mode.MAPPING:
            raise Conflict("already mapping: stop or cancel it first")
        navigating_here = self._mode is Mode.NAVIGATING and self._map_name == name
        if self._mode is not Mode.FREE and not navigating_here:
            raise Conflict(f"updating map {name!r} starts from free, or while navigating on it "
                           f"(mode {self._mode.value}, map {self._map_name!r})")
        if navigating_here and self._goal_active():
            raise Conflict("a goal is active: cancel it before updating the map")
        stack = self._stack
        if initial is None and navigating_here and stack is not None:
            estimate = stack.estimate
            if estimate.state is LocalizationState.TRACKING:
                initial = estimate.pose
        if initial is None:
            if self._floor_now() != floor:
                raise Conflict(f"map {name!r} is of floor {floor}, the robot is on "
                               f"{self._floor_now()}: give its point or pose on the map")
            scan = self._robot.read_scan()
            if scan is None:
                raise NotLocalized("no scan yet to find the robot on the map: give its point "
                                   "or pose")
            found = Relocalizer(grid).locate(scan)
            if found.pose is None:
                raise NotLocalized(f"the robot is not found on map {name!r}: {found.reason} "
                                   f"(score {found.score:.2f}); give its point or pose")
            initial = found.pose
        try:
            session = MappingSession(floor, initial, name=name, prior=grid,
                                     started_at=self.now())
        except ValueError as exc:
            raise InvalidRequest("map", f"map {name!r} cannot be extended: {exc}") from exc
        self._place.place(floor, initial)  # may raise before anything changed
        if navigating_here:
            self._stop_navigation()
        self._halt_motion()
        self._mapping = session
        self._mapping_jobs.new_session()
        self._set_mode(Mode.MAPPING)
        log.info("updating map %r on floor %s from %s", name, floor, initial)

    def explore(self) -> None:
        """Let the robot map on its own: it drives to the nearest frontier of the live map,
        again and again, then back to where exploring began (``exploration_finished``).
        Teleop or a local move takes over while it runs.

        Raises:
            Conflict: not mapping; already exploring.
        """

        def run() -> None:
            session = self._require_mapping()
            if self._exploration is not None and not self._exploration.done:
                raise Conflict("already exploring")
            self._exploration = Exploration(session.pose)
            log.info("exploration started at %s", session.pose)

        self._call(run)

    def mapping_map(self) -> Map:
        """The map built so far.

        Raises:
            Conflict: not mapping.
        """
        return self._call(lambda: self._require_mapping().live_map())

    def mapping_trajectory(self) -> list[Pose2D]:
        """The robot's path while mapping (the scan poses, optimised).

        Raises:
            Conflict: not mapping.
        """
        return self._call(lambda: self._require_mapping().trajectory())

    def save_mapping(self, name: str, *, overwrite: bool = False) -> object:
        """Save the map built so far under ``name`` (ROS map files in the site store); mapping
        goes on. Returns the saved map's record. A map being updated may be saved under its
        own name without ``overwrite`` (its points and keepouts stay: the frame is the same).

        The map is rendered between ticks and written on the calling thread; the job it is
        (:meth:`save_mapping_job`) shows in the status meanwhile.

        Raises:
            Conflict: not mapping; ``name`` exists and ``overwrite`` is not set; a save runs.
            InvalidRequest: a bad name.
            StorageError: the files could not be written (the job failed).
        """
        return self._run_job(self._call(lambda: self._begin_job(JobKind.SAVE, name, overwrite)))

    def stop_mapping(self, name: str, *, overwrite: bool = False) -> object:
        """Finish the map (a last optimisation of the whole graph), save it under ``name``, and
        become FREE; returns the saved map's record. Nothing is lost when saving fails: the
        robot maps on.

        The dialects' synchronous form: the finish and the save run on the calling thread (off
        the loop thread, unless called from it), the robot BUSY meanwhile; the native API
        starts the same work as a job (:meth:`stop_mapping_job`) and answers at once.

        Raises:
            Conflict: not mapping; ``name`` exists and ``overwrite`` is not set; a save runs.
            InvalidRequest: a bad name.
            StorageError: the files could not be written (the job failed; mapping goes on).
        """
        return self._run_job(self._call(lambda: self._begin_job(JobKind.STOP, name, overwrite)))

    def save_mapping_job(self, name: str, *, overwrite: bool = False) -> MappingJob:
        """Start saving the map so far under ``name`` on a worker thread; mapping goes on.
        Returns the job (``saving``); :meth:`mapping_job` and the status follow it.

        Raises (at once, before any job):
            Conflict: not mapping; ``name`` exists and ``overwrite`` is not set; a save runs.
            InvalidRequest: a bad name.
        """
        return self._spawn(self._call(lambda: self._begin_job(JobKind.SAVE, name, overwrite)))

    def stop_mapping_job(self, name: str, *, overwrite: bool = False) -> MappingJob:
        """Start finishing the map and saving it under ``name`` on a worker thread, the robot
        BUSY (halted, its control loop running) until it is saved, then FREE; a failed save
        leaves it MAPPING again, nothing lost. Returns the job (``saving``).

        Raises (at once, before any job):
            Conflict: not mapping (a stop job runs: the robot is BUSY); ``name`` exists and
                ``overwrite`` is not set; a save runs.
            InvalidRequest: a bad name.
        """
        return self._spawn(self._call(lambda: self._begin_job(JobKind.STOP, name, overwrite)))

    def mapping_job(self, job_id: str) -> MappingJob:
        """A save job as it is now (any thread, never waits).

        Raises:
            NotFound: no such job (only the last few are kept).
        """
        return self._mapping_jobs.get(job_id)

    def cancel_mapping(self) -> None:
        """Drop the map being built and become FREE.

        Raises:
            Conflict: not mapping.
        """

        def run() -> None:
            self._require_mapping()
            self._end_mapping()

        self._call(run)

    def _require_mapping(self) -> MappingSession:
        if self._mapping_jobs.finishing is not None:
            job = self._mapping_jobs.session_job()
            what = "" if job is None else f": map {job.name!r} is being saved (job {job.id})"
            raise Conflict(f"mapping is stopping{what}")
        if self._mode is not Mode.MAPPING or self._mapping is None:
            raise Conflict(f"not mapping (mode {self._mode.value}): start mapping first")
        return self._mapping

    def _mapping_status(self, now: float) -> MappingStatus | None:
        """The status's ``mapping`` part (between ticks): the session, or the session a stop
        job finishes; ``None`` otherwise."""
        jobs = self._mapping_jobs
        if self._mapping is not None:
            return mapping_status(self._mapping, self._exploration, now, jobs.session_job())
        if jobs.finishing is not None:
            return jobs.finishing.with_job(jobs.session_job())
        return None

    # -- save jobs: checked and begun between ticks, the heavy part on a worker thread ---------

    def _begin_job(self, kind: JobKind, name: str, overwrite: bool) -> _Work:
        """Check everything that can be checked at once, then begin the job (between ticks).
        A save renders the map here (it changes with every scan: the worker cannot read it);
        a stop takes the session off the loop for the worker to finish, the robot BUSY."""
        session = self._require_mapping()
        check_name("name", name)
        self._check_name_free(session, name, overwrite)
        job = self._mapping_jobs.begin(kind, name, self.now())
        if kind is JobKind.SAVE:
            return _Work(job, session, overwrite, session.live_map())
        self._mapping_jobs.finishing = mapping_status(session, self._exploration, self.now(),
                                                      job)
        self._halt_motion()
        self._mapping = None
        self._exploration = None
        self._set_mode(Mode.BUSY)
        log.info("mapping stops: finishing map %r (job %s)", name, job.id)
        return _Work(job, session, overwrite, None)

    def _spawn(self, work: _Work) -> MappingJob:
        """Run ``work`` on a worker thread; its job as it begins."""

        def run() -> None:
            try:
                self._run_job(work)
            except Exception:  # recorded in the job (and logged) by _run_job
                pass

        # Not a daemon: a map being written is finished before the process exits.
        threading.Thread(target=run, name=f"polynav-mapping-job-{work.job.id}").start()
        return work.job

    def _run_job(self, work: _Work) -> object:
        """The heavy part (finish, render, write the files) on this thread, then the outcome
        applied between ticks; returns the saved map's record or raises what failed."""
        try:
            grid = work.grid if work.grid is not None else work.session.finish()
            record = self._write_map(work.session, grid, work.job.name, work.overwrite)
        except Exception as exc:
            if not isinstance(exc, PolynavError):
                log.exception("mapping job %s failed", work.job.id)
            error = str(exc) or type(exc).__name__
            self._loop.call(lambda: self._end_job(work, error))
            raise
        self._loop.call(lambda: self._end_job(work, None))
        return record

    def _end_job(self, work: _Work, error: str | None) -> None:
        """The job's outcome, between ticks: a stop that saved ends mapping (FREE); one that
        failed hands the session back to the loop (MAPPING, driven by hand again)."""
        self._mapping_jobs.end(work.job.id, self.now(), error)
        if work.job.kind is not JobKind.STOP:
            return
        self._mapping_jobs.finishing = None
        if error is None:
            self._end_mapping()
            return
        self._mapping = work.session
        self._set_mode(Mode.MAPPING)

    def _check_name_free(self, session: MappingSession, name: str, overwrite: bool) -> None:
        if overwrite or session.name == name:
            return
        try:
            self.store.map_record(name)
        except NotFound:
            return
        raise Conflict(f"a map called {name!r} exists: give another name, or overwrite it")

    def _write_map(self, session: MappingSession, grid: Map, name: str,
                   overwrite: bool) -> object:
        """Save ``grid`` in the site store (any thread: the store has its own lock)."""
        self._check_name_free(session, name, overwrite)  # taken since the job began?
        floor = session.floor
        if floor is not None:
            try:
                self.store.floor(floor)
            except NotFound:  # a simulated floor the site does not know: the map has none
                floor = None
        record = self.store.save_map(name, grid, floor=floor)
        log.info("map %r saved (%d x %d cells)", name, grid.info.width, grid.info.height)
        return record

    @abc.abstractmethod
    def _refuse_if_shutting_down(self, what: str) -> None:
        """Conflict while a shutdown is announced (the runtime's power cycle)."""

    def _end_mapping(self) -> None:
        self._halt_motion()
        self._mapping = None
        self._exploration = None
        self._set_mode(Mode.FREE)


@dataclass(frozen=True, slots=True)
class _Work:
    """A begun job and what its worker needs: the session, and for a save the map rendered."""

    job: MappingJob
    session: MappingSession
    overwrite: bool
    grid: Map | None
