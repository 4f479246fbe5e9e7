"""A simulated driven axis: a slide table, a jacking lift or a jacking turntable.

The axis moves at a constant speed (the asked one, or its default) toward its target and stops
there; time is the runtime's clock, and the axis is advanced to ``now`` on every call, so its
motion does not depend on how often it is asked. At power-on it does not know where it is
(``homed`` false) although it stands somewhere (``true_position``); a position or ratio move
first runs to the zero switch at the homing speed and then on to the target, as a stepper
driver with a limit switch does. A linear axis has a travel and stops at its ends (limit
protection); a rotary one (``travel`` ``None``) turns freely and wraps the angle.
"""

from __future__ import annotations

import itertools
import logging
import math
from dataclasses import dataclass

from polynav.errors import InvalidRequest
from polynav.geometry import wrap_angle
from polynav.robot.devices import AxisMode, AxisState, DeviceJob, JobState

log = logging.getLogger(__name__)

_EPS = 1e-9


@dataclass(frozen=True, slots=True)
class AxisConfig:
    """An axis: name, travel [m] (``None``: rotary, [rad]), default, homing and top speeds
    [m/s or rad/s], where it stands at power-on."""

    name: str
    travel: float | None
    default_speed: float
    homing_speed: float
    max_speed: float
    start_position: float = 0.0


@dataclass(slots=True)
class _Segment:
    target: float
    speed: float
    homes: bool = False  # reaching the target finds the zero switch


class SimAxis:
    """One simulated axis (implements :class:`~polynav.robot.devices.Axis`)."""

    def __init__(self, config: AxisConfig, now: float = 0.0) -> None:
        self.config = config
        self.true_position = config.start_position
        self._homed = False
        self._fault = False
        self._t = now
        self._plan: list[_Segment] = []
        self._jog_until: float | None = None
        self._job: DeviceJob | None = None
        self._job_length = 0.0
        self._jobs: dict[str, DeviceJob] = {}
        self._ids = itertools.count(1)

    # -- reads -----------------------------------------------------------------------------

    def advance(self, now: float) -> None:
        """Bring the axis to ``now`` (what :meth:`state` does before it reports)."""
        self._advance(now)

    def state(self, now: float) -> AxisState:
        self._advance(now)
        travel = self.config.travel
        ratio = self.true_position / travel if travel else 0.0
        position = self.true_position if travel else wrap_angle(self.true_position)
        homed = self._homed
        return AxisState(homed, self._fault, position if homed else 0.0,
                         ratio if homed else 0.0, self._moving())

    def job(self, now: float, job_id: str) -> DeviceJob | None:
        self._advance(now)
        return self._jobs.get(job_id)

    # -- commands --------------------------------------------------------------------------

    def move(
        self, now: float, mode: AxisMode, *, target: float = 0.0, speed: float = 0.0,
        duration: float = 0.0,
    ) -> DeviceJob:
        """Start a move; a running one is cancelled. See :class:`~polynav.robot.devices.Axis`.

        Raises:
            InvalidRequest: a non-finite value, a target outside the travel, a ratio outside
                0..1, a negative speed outside jog mode, a jog without a positive time, or a
                mode a rotary axis has not (ratio).
        """
        c = self.config
        self._advance(now)
        for key, value in (("target", target), ("speed", speed), ("duration", duration)):
            if not math.isfinite(value):
                raise InvalidRequest(key, f"must be a finite number, got {value}")
        if mode is not AxisMode.JOG and speed < 0.0:
            raise InvalidRequest("speed", f"must be >= 0 outside jog mode, got {speed}")
        magnitude = min(abs(speed) or c.default_speed, c.max_speed)
        plan: list[_Segment] = []
        if mode is AxisMode.JOG:
            if not duration > 0.0:
                raise InvalidRequest("time", f"a jog needs a run time > 0 s, got {duration}")
            direction = -1.0 if speed < 0.0 else 1.0
            goal = self.true_position + direction * magnitude * duration
            if c.travel is not None:
                goal = min(max(goal, 0.0), c.travel)
            plan.append(_Segment(goal, magnitude))
        elif mode is AxisMode.HOME:
            plan.append(_Segment(0.0, c.homing_speed, homes=True))
        else:
            if mode is AxisMode.RATIO:
                if c.travel is None:
                    raise InvalidRequest("mode", f"{c.name} turns: it has no ratio mode")
                if not 0.0 <= target <= 1.0 + _EPS:
                    raise InvalidRequest("pose", f"a ratio must be in 0..1, got {target}")
                goal = min(target, 1.0) * c.travel
            elif c.travel is not None:
                if not -_EPS <= target <= c.travel + _EPS:
                    raise InvalidRequest(
                        "pose", f"{c.name} travels 0..{c.travel:g} m, got {target:g}")
                goal = min(max(target, 0.0), c.travel)
            else:
                goal = target
            if not self._homed:
                plan.append(_Segment(0.0, c.homing_speed, homes=True))
            plan.append(_Segment(goal, magnitude))
        if c.travel is None and mode is not AxisMode.JOG:
            # A turntable takes the short way round to an angle.
            self.true_position = wrap_angle(self.true_position)
            for seg in plan:
                seg.target = self.true_position + _short_way(self.true_position, seg.target)
        self._finish(JobState.CANCELLED)
        self._fault = False
        self._plan = plan
        job = DeviceJob(f"{c.name}-{next(self._ids)}", c.name, JobState.WORKING, 0.0, now)
        self._job = job
        self._jobs[job.job_id] = job
        self._job_length = self._plan_length()
        log.info("%s: %s move to %.3f at %.3f", c.name, mode.name.lower(), plan[-1].target,
                 plan[-1].speed)
        self._update_progress()
        return job

    def stop(self, now: float) -> None:
        """Stop where it is; a running job ends CANCELLED."""
        self._advance(now)
        self._plan = []
        self._finish(JobState.CANCELLED)

    def set_fault(self, now: float, reason: str) -> None:
        """Break the axis (tests and demos): it stops, the job ends in ERROR, it must re-home."""
        self._advance(now)
        self._plan = []
        self._fault = True
        self._homed = False
        self._finish(JobState.ERROR, reason)

    # -- motion on the clock ---------------------------------------------------------------

    def _advance(self, now: float) -> None:
        dt = now - self._t
        if dt <= 0.0:
            return
        self._t = now
        while self._plan and dt > _EPS:
            seg = self._plan[0]
            gap = seg.target - self.true_position
            need = abs(gap) / seg.speed if seg.speed > 0.0 else math.inf
            if need <= dt:
                self.true_position = seg.target
                dt -= need
                self._plan.pop(0)
                if seg.homes:
                    self._homed = True
            else:
                self.true_position += math.copysign(seg.speed * dt, gap)
                dt = 0.0
        self._update_progress()
        if not self._plan:
            self._finish(JobState.COMPLETE)

    def _moving(self) -> bool:
        return bool(self._plan)

    def _plan_length(self) -> float:
        position, total = self.true_position, 0.0
        for seg in self._plan:
            total += abs(seg.target - position)
            position = seg.target
        return total

    def _update_progress(self) -> None:
        job = self._job
        if job is None or job.state is not JobState.WORKING:
            return
        left = self._plan_length()
        progress = 1.0 if self._job_length <= _EPS else 1.0 - left / self._job_length
        self._store(DeviceJob(job.job_id, job.kind, job.state, round(progress, 6), job.started))

    def _finish(self, state: JobState, reason: str = "") -> None:
        job = self._job
        if job is None or job.state is not JobState.WORKING:
            return
        progress = 1.0 if state is JobState.COMPLETE else job.progress
        self._store(DeviceJob(job.job_id, job.kind, state, progress, job.started, reason))
        if state is JobState.COMPLETE and self.config.travel is None:
            self.true_position = wrap_angle(self.true_position)

    def _store(self, job: DeviceJob) -> None:
        self._job = job
        self._jobs[job.job_id] = job
        while len(self._jobs) > 256:  # ids are never reused; keep the recent ones
            del self._jobs[next(iter(self._jobs))]


def _short_way(current: float, target: float) -> float:
    return wrap_angle(target - current)
