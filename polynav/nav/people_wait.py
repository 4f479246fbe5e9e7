"""Waiting for people to make way: the navigator's *wait* phase.

When only people block the way (a person in a door, someone coming down a narrow corridor), a
robot that re-plans and recovers as it would for a box gets nowhere, and one that fails at once
fails where a few seconds of patience would have done. :class:`PeopleWait` runs the wait: it
stands, looks for a way past the people every ``wait_replan_period`` on the live costmap, goes on
as soon as the way is open, and after ``give_way_after`` face to face with someone it steps
aside off their way (or backs up where there is no room) so that they can pass, as a person
would; a spot aside is one reached about straight, never one round a wall, and never farther
than ``_ASIDE_REACH`` from where the wait began (a step, not a retreat). The patience runs
over the whole episode, which ends once the robot has got ``reset_distance`` past where it
began; when it runs out the goal fails ``blocked by person``. The stretches it drives on its
path between waits, or stands paused, do not count: at a door a walker shuttles through, a
robot that followed them in, met them coming back and gave way again failed after 60 s of
which much was driving, 0.94 m short of a new episode (issue 36, bench fleet seed 2, floor 2's
room_205).

A goal paused to wait in line (the fleet's traffic rule, a shut door) still makes way
(:meth:`PeopleWait.make_way`): someone held up face to face with the robot for ``give_way_after``
sees it step aside as it would while waiting for them. Standing frozen in line, a robot held
a walker in a corridor while the robot ahead, holding the passage, waited for that walker
(issue 36: floor 2's room_205 door). An operator's pause stays a standstill.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from polynav.control.interface import Controller, ControlStatus
from polynav.footprint import Footprint
from polynav.geometry import Pose2D, Twist
from polynav.maps.costmap import Costmap
from polynav.nav.people import PeopleConfig, PeopleView, aside_spots, densify
from polynav.nav.recoveries import BackUp
from polynav.planning.errors import PlanningError
from polynav.planning.interface import GlobalPlanner
from polynav.planning.path import Path

log = logging.getLogger(__name__)

_FACE_TO_FACE_MARGIN = 0.4  # [m] beyond the social distance: someone this near is face to face
_HELD_SPEED = 0.02  # [m/s] slowed below this for people, the robot counts as held by them
_ASIDE_MARGIN = 0.1  # [m] beyond the social distance: stepping aside closes in on no one here
_CLOSING_LEAD = 0.5  # [s] ahead that someone coming on is judged (tracker lag, braking)
_ASIDE_TRIES = 2  # spots tried in one give-way before backing up
_ASIDE_CREEP = 0.005  # [m/s] the most the robot closes in on someone there while stepping aside
_ASIDE_DETOUR = 1.5  # a way aside longer than this times the straight distance is no step aside
_ASIDE_SLACK = 0.3  # [m] beyond that: a grid path's steps round a corner
_ASIDE_REACH = 2.0  # [m] from where the wait began: a spot farther is no step aside
_STANDING = 0.1  # [m/s] someone slower than this stands (held up, maybe, by the robot)


def _judged_gap(d: float, radial: float) -> float:
    """The gap [m] to someone ``d`` away whose walk along it is ``radial`` [m/s] (negative:
    coming on), judged where they will be :data:`_CLOSING_LEAD` from now: the tracked legs
    lag, and a robot at speed does not stop at once."""
    return d + min(0.0, radial) * _CLOSING_LEAD


@dataclass(frozen=True, slots=True)
class WaitStep:
    """What one period of waiting asks of the navigator."""

    twist: Twist = Twist()  # command this and keep waiting
    path: Path | None = None  # a way past the people: follow it
    go_on: bool = False  # the way is open: plan again
    expired: bool = False  # the patience ran out: fail the goal


class PeopleWait:
    """The people seen each period, and the current wait for them (one goal at a time)."""

    def __init__(
        self,
        config: PeopleConfig,
        costmap: Costmap,
        planner: GlobalPlanner,
        controller: Controller,
        *,
        robot_radius: float,
        footprint: Footprint | None = None,
    ) -> None:
        self.config = config
        self._costmap = costmap
        self._planner = planner
        self._controller = controller
        self._robot_radius = robot_radius
        self.people = PeopleView()
        self._since: float | None = None
        self._credit = 0.0  # [s] of this episode not spent waiting (driving, paused)
        self._paused_at: float | None = None
        self._where: Pose2D | None = None
        self._last_plan = 0.0
        self._last_give_way = 0.0
        # The body itself is checked backing up: a wall behind and to a side is missed by a
        # probe on the centre line (a disk robot backed into a corridor's wall giving way).
        self._back_up = BackUp(
            costmap, distance=config.give_way_distance, speed=0.15,
            robot_radius=robot_radius, timeout=8.0, footprint=footprint,
        )
        self._backing_up = False
        self._aside: Pose2D | None = None
        self._aside_held_since: float | None = None
        self._aside_tries = 0
        self._held_since: float | None = None
        self._paused_where: Pose2D | None = None  # where a paused goal began making way
        self._facing_since: float | None = None  # someone held up face to face, paused

    def reset(self) -> None:
        """A new goal: no wait."""
        self._since = None
        self._where = None
        self._held_since = None
        self._credit = 0.0
        self._paused_at = None
        self._paused_where = None
        self._facing_since = None

    def pause(self, now: float) -> None:
        """The goal is paused: the time until :meth:`resume` is not spent waiting for people."""
        self._paused_at = now

    def resume(self, now: float) -> None:
        """The goal goes on: a wait begun before the pause keeps the patience it had left, and
        a step aside made while paused is over.

        Paused time counted against it, a robot that stood 3 minutes in line for a corridor
        (the fleet pauses its goal) right after a walker had made way failed ``blocked by
        person`` the moment the next walker came by, with no wait at all (issue 36).
        """
        if self._paused_at is not None and self._since is not None:
            self._credit += now - self._paused_at
        self._paused_at = None
        self._paused_where = None
        self._facing_since = None
        self._aside = None
        self._backing_up = False

    def make_way(self, pose: Pose2D, velocity: Twist, now: float, dt: float) -> Twist:
        """One period of a goal paused to wait in line: standing, but stepping aside (or
        backing up) once someone has stood held up face to face with the robot for
        ``give_way_after``, no farther than :data:`_ASIDE_REACH` from where it was paused.
        The goal resumes with a fresh plan, so the move costs it nothing but the step."""
        if self._paused_where is None:
            self._paused_where = pose
        twist = self._tick_give_way(pose, velocity, now, dt)
        if twist is not None:
            return twist
        cfg = self.config
        standing = [p for p in self.people.people if math.hypot(p.vx, p.vy) <= _STANDING]
        facing = cfg.enabled and any(
            math.hypot(p.x - pose.x, p.y - pose.y) <= cfg.social_distance + _FACE_TO_FACE_MARGIN
            for p in standing)
        if not facing:
            self._facing_since = None
            return Twist()
        if self._facing_since is None:
            self._facing_since = now
        if now - self._facing_since < cfg.give_way_after:
            return Twist()
        self._facing_since = None
        self._aside_tries = 0
        log.info("paused, and someone waits for the robot to make way")
        self._start_give_way(pose, now)
        return self._tick_give_way(pose, velocity, now, dt) or Twist()

    def moved(self, pose: Pose2D, distance: float) -> None:
        """The robot is following its path: ``distance`` past where it waited, the wait is over
        and a later one has its own patience."""
        if self._where is not None and pose.distance_to(self._where) >= distance:
            self._since = None
            self._credit = 0.0
            self._where = None

    def drove(self, dt: float) -> None:
        """The robot drove on its path for ``dt``: not time spent waiting for people."""
        if self._since is not None:
            self._credit += dt

    def blocks(self, pose: Pose2D, path: Path | None) -> bool:
        """Whether people may be what blocks the way: someone close to the robot, or to the
        path within ``block_lookahead`` of it."""
        people, cfg = self.people, self.config
        if not people or not cfg.enabled:
            return False
        if people.nearest(pose.x, pose.y) <= cfg.block_radius + self._robot_radius:
            return True
        if path is None:
            return False
        points = densify(np.asarray(path.points, dtype=np.float64), 0.1)
        ahead = np.hypot(points[:, 0] - pose.x, points[:, 1] - pose.y) <= cfg.block_lookahead
        return people.near_any(points[ahead], cfg.block_radius)

    def begin(self, pose: Pose2D, now: float) -> bool:
        """Start (or go back to) waiting; ``True`` when this begins a new wait."""
        new = self._since is None
        if new:
            self._since = now
            self._credit = 0.0
            self._where = pose
            self._last_give_way = now  # give way after a while of this wait, however it goes
            log.info("people block the way: waiting up to %g s", self.config.patience)
        self._controller.reset()
        self._last_plan = now
        self._held_since = None
        self._backing_up = False
        self._aside = None
        return new

    def tick(
        self,
        pose: Pose2D,
        velocity: Twist,
        now: float,
        dt: float,
        path: Path | None,
        plan: Callable[[Pose2D], Path],
    ) -> WaitStep:
        """One period of the wait; ``path`` is the way the robot was going, ``plan`` plans to
        the goal on the live costmap."""
        cfg = self.config
        assert self._since is not None, "begin() first"
        if now - self._since - self._credit >= cfg.patience:
            return WaitStep(expired=True)
        twist = self._tick_give_way(pose, velocity, now, dt)
        if twist is not None:
            return WaitStep(twist)
        if not self.blocks(pose, path) and not (path is None and self.people):
            # (With no path yet, people in view may be anywhere on the way: look for one.)
            log.info("the way is open: re-planning")
            return WaitStep(go_on=True)
        face_to_face = self.people.nearest(pose.x, pose.y) <= (
            cfg.social_distance + _FACE_TO_FACE_MARGIN
        )
        if face_to_face and now - self._last_give_way >= cfg.give_way_after:
            self._aside_tries = 0
            self._start_give_way(pose, now)
            return WaitStep(self._tick_give_way(pose, velocity, now, dt) or Twist())
        if now - self._last_plan < cfg.wait_replan_period:
            return WaitStep()
        self._last_plan = now
        try:
            # On the live costmap, where the people's legs are obstacles: a path is a way past
            # them (round them in a corridor, through another door) or a sign they moved.
            way = plan(pose)
        except PlanningError:
            return WaitStep()
        log.info("a way past the people: following it")
        return WaitStep(path=way)

    def slow(self, pose: Pose2D, twist: Twist, now: float | None = None) -> Twist:
        """``twist`` made polite, on the same curvature: no more than the slow speed within the
        social distance of someone, and no closing in on anyone near it.

        The robot's own speed towards a person (its velocity along the line to them, less the
        speed at which they walk away) may be at most ``(d - social_distance) /
        approach_time`` at distance ``d``: the robot eases up to the edge of their space and
        stops there, rather than drive into it; moving past, away, or turning is not limited.
        Someone walking towards the robot counts at ``d`` less their closing walk over
        :data:`_CLOSING_LEAD` (the tracker lags, and the robot needs time to brake).
        The plan (people layer) is what keeps the robot clear where there is room; this holds
        the line when the plan is late, or when there is no room and the wait takes over.
        With ``now`` given, a robot held still this way is remembered (:meth:`held`).
        """
        polite = self._polite(pose, twist)
        if now is not None:
            stopped = abs(polite.linear) < _HELD_SPEED <= abs(twist.linear)
            if not stopped:
                self._held_since = None
            elif self._held_since is None:
                self._held_since = now
        return polite

    def held(self, now: float) -> bool:
        """Whether :meth:`slow` has kept the robot from moving for ``hold_before_wait``: the
        people are in the way, and the wait (re-plans, giving way) should take over."""
        since = self._held_since
        return since is not None and now - since >= self.config.hold_before_wait

    def _polite(self, pose: Pose2D, twist: Twist, *, approach: bool = True) -> Twist:
        cfg = self.config
        speed = abs(twist.linear)
        if not cfg.enabled or speed == 0.0 or not self.people:
            return twist
        sign = 1.0 if twist.linear > 0.0 else -1.0
        hx, hy = sign * math.cos(pose.theta), sign * math.sin(pose.theta)
        limit = speed
        for p in self.people.people:
            dx, dy = p.x - pose.x, p.y - pose.y
            d = math.hypot(dx, dy)
            if d < cfg.social_distance:
                limit = min(limit, cfg.slow_speed)
            if not approach:
                continue
            towards = 0.0 if d == 0.0 else (dx * hx + dy * hy) / d  # cos(motion, person)
            if towards <= 0.0:
                continue
            radial = (p.vx * dx + p.vy * dy) / d
            ahead = _judged_gap(d, radial)
            allowed = max(0.0, ahead - cfg.social_distance) / cfg.approach_time + max(0.0, radial)
            limit = min(limit, allowed / towards)
        if limit >= speed:
            return twist
        k = limit / speed
        return Twist(twist.linear * k, twist.angular * k)

    def _aside_polite(self, pose: Pose2D, twist: Twist) -> Twist:
        """``twist`` while stepping aside: slow near people, and no closing in on anyone within
        the social distance (plus :data:`_ASIDE_MARGIN`), but the turn is kept.

        A walker coming on closes the gap anyway; the robot's own part is the component of its
        velocity towards them, which is cut to :data:`_ASIDE_CREEP`. Unlike :meth:`_polite`,
        the angular velocity is not scaled with the linear one: the robot keeps turning
        towards its way aside (which :func:`aside_spots` chose leading away from people) and
        drives on once it faces away from them, instead of standing face to face.
        """
        twist = self._polite(pose, twist, approach=False)
        speed = abs(twist.linear)
        if speed == 0.0:
            return twist
        sign = 1.0 if twist.linear > 0.0 else -1.0
        hx, hy = sign * math.cos(pose.theta), sign * math.sin(pose.theta)
        limit = speed
        reach = self.config.social_distance + _ASIDE_MARGIN
        for p in self.people.people:
            dx, dy = p.x - pose.x, p.y - pose.y
            d = math.hypot(dx, dy)
            if d == 0.0 or _judged_gap(d, (p.vx * dx + p.vy * dy) / d) >= reach:
                continue
            towards = (dx * hx + dy * hy) / d
            if towards > 0.0:
                limit = min(limit, _ASIDE_CREEP / towards)
        if limit >= speed:
            return twist
        return Twist(sign * limit, twist.angular)

    def _start_give_way(self, pose: Pose2D, now: float) -> None:
        """Step aside (or back up), within reach of where the goal was paused, if it is (see
        :meth:`make_way`), else of where the wait began."""
        self._aside_held_since = None
        self._aside_tries += 1
        anchor = self._paused_where if self._paused_where is not None else self._where
        for spot in aside_spots(self._costmap, pose, self.people, self.config):
            if anchor is not None and spot.distance_to(anchor) > _ASIDE_REACH:
                # Step after step away from one walker coming on is a retreat, not a step
                # aside: a robot on floor 2's corridor stepped into a room's side passage,
                # then down it ahead of the walker heading there, into the room, 4 m off its
                # way; coming back it met a robot its lease shared the corridor with, head-on
                # in the passage (issue 36, bench fleet seed 0).
                continue
            try:
                way = self._planner.plan(self._costmap, pose, spot)
            except PlanningError:
                continue
            if way.length > _ASIDE_DETOUR * pose.distance_to(spot) + _ASIDE_SLACK:
                # A spot behind a wall, reached round it through the next door, is no step
                # aside: the robot drove 5-8 m, back down the passage the walker was heading
                # for, and met them again (issue 36: 170 s in floor 2's corridor zone while
                # six robots queued for it).
                log.debug("giving way: (%.2f, %.2f) is %.1f m away round a wall", spot.x,
                          spot.y, way.length)
                continue
            log.info("giving way: stepping aside to (%.2f, %.2f)", spot.x, spot.y)
            self._aside = spot
            self._controller.reset()
            self._controller.set_path(way, spot)
            return
        log.info("giving way: backing up %.2f m", self.config.give_way_distance)
        self._backing_up = True
        self._back_up.start(pose, now)

    def _tick_give_way(self, pose: Pose2D, velocity: Twist, now: float, dt: float) -> Twist | None:
        """The velocity while stepping aside or backing up, ``None`` when not (or done)."""
        if self._aside is not None:
            command = self._controller.compute(pose, velocity, self._costmap, dt)
            if command.status not in (ControlStatus.ARRIVED, ControlStatus.BLOCKED):
                # Slowly, closing in on no one near, but turning on: standing still face to
                # face is what this move ends.
                twist = self._aside_polite(pose, command.twist)
                if abs(twist.linear) >= _HELD_SPEED or abs(command.twist.linear) < _HELD_SPEED:
                    self._aside_held_since = None
                elif self._aside_held_since is None:
                    self._aside_held_since = now
                elif now - self._aside_held_since >= self.config.hold_before_wait:
                    # Someone came into the way aside: another spot for where they are now,
                    # once; after that backing off (or standing) leaves them room.
                    self._aside = None
                    self._controller.reset()
                    if self._aside_tries < _ASIDE_TRIES:
                        self._start_give_way(pose, now)
                    else:
                        log.info("giving way: backing up %.2f m", self.config.give_way_distance)
                        self._backing_up = True
                        self._back_up.start(pose, now)
                    return self._tick_give_way(pose, velocity, now, dt) or Twist()
                return twist
            self._aside = None
            self._controller.reset()
            self._last_give_way = now
            return None
        if self._backing_up:
            back = self._back_up.tick(pose, now)
            if back is not None:
                return self._polite(pose, back)  # not into someone behind
            self._backing_up = False
            self._last_give_way = now
        return None
