"""Clutter courses: a walled box full of obstacles, start and goal 10 m apart across it.

Issue 18's test of navigation at speed among obstacles the planner was never tuned on, and
issue 31's courses that look like the world. A course is drawn from a seed, a *kind* and a
*density* between 0 (sparse) and 1 (barely passable); the kinds, by name in :data:`KINDS`:

- ``posts`` (:mod:`polynav.worlds.clutter_posts`): thin posts thrown at random, every gap at
  least a body width plus a margin;
- ``lattice`` (:mod:`polynav.worlds.clutter_lattice`): posts on a lattice packed into short
  walls, hooks, pockets open towards the start and small boxes, with many gaps wider than the
  body but narrower than its diagonal, some across the straight line from start to goal.

Each kind has a construction that guarantees a way for the body and a check of it after the
draw; a course that fails its check is drawn again from the next sub-seed, so what the
benchmark drives is always feasible. Everything is in metres on a 0.05 m grid; the same kind,
spec and seed always draw the same course.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from polynav.errors import InvalidRequest
from polynav.footprint import Footprint
from polynav.worlds import clutter_lattice, clutter_posts
from polynav.worlds.clutter_course import (
    RESOLUTION,
    WALL,
    ClutterCourse,
    ClutterSpec,
    CourseError,
    Gap,
    Structure,
)
from polynav.worlds.clutter_posts import min_gap_for

log = logging.getLogger(__name__)

__all__ = [
    "KINDS",
    "RESOLUTION",
    "WALL",
    "ClutterCourse",
    "ClutterSpec",
    "CourseError",
    "CourseKind",
    "Gap",
    "Structure",
    "check",
    "draw",
    "min_gap_for",
]


@dataclass(frozen=True, slots=True)
class CourseKind:
    """How one kind draws a course (unchecked) and checks the guarantee of a drawn one."""

    draw_once: Callable[[Footprint, ClutterSpec, np.random.Generator, int], ClutterCourse]
    check: Callable[[ClutterCourse, Footprint], str | None]


KINDS: dict[str, CourseKind] = {
    "posts": CourseKind(clutter_posts.draw_once, clutter_posts.check),
    "lattice": CourseKind(clutter_lattice.draw_once, clutter_lattice.check),
}
"""Course kinds by name (``ClutterSpec.kind``)."""


def course_kind(name: str) -> CourseKind:
    """The kind named ``name``.

    Raises:
        InvalidRequest: no such kind (``field`` ``kind``).
    """
    try:
        return KINDS[name]
    except KeyError:
        raise InvalidRequest(
            "kind", f"{name!r} is not one of {', '.join(sorted(KINDS))}"
        ) from None


def draw(footprint: Footprint, spec: ClutterSpec, seed: int, *, tries: int = 20) -> ClutterCourse:
    """Draw and check a course of ``spec.kind`` for ``footprint`` (see the module docstring).

    Draw ``k`` uses the generator seeded with ``[seed, k]``, so a course is a function of the
    spec, the seed and the footprint alone.

    Raises:
        InvalidRequest: ``spec.kind`` is not a kind.
        CourseError: ``tries`` draws in a row failed the feasibility check.
    """
    kind = course_kind(spec.kind)
    for k in range(tries):
        rng = np.random.default_rng([seed, k])
        course = kind.draw_once(footprint, spec, rng, seed)
        problem = kind.check(course, footprint)
        if problem is None:
            return course
        log.warning("clutter %s course %d draw %d rejected: %s", spec.kind, seed, k, problem)
    raise CourseError(f"no feasible {spec.kind} clutter course from seed {seed} in {tries} draws")


def check(course: ClutterCourse, footprint: Footprint) -> str | None:
    """``None`` if ``course`` keeps its kind's guarantee for ``footprint``, else why not."""
    return course_kind(course.kind).check(course, footprint)
