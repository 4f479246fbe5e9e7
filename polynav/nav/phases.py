"""The navigator's inner phases while an attempt runs (module docstring of
:mod:`~polynav.nav.navigator`); a module of their own so its mixins can name them."""

from __future__ import annotations

import enum


class NavPhase(enum.Enum):
    PLAN = "plan"
    FOLLOW = "follow"
    BLOCKED = "blocked"
    RECOVER = "recover"
    WAIT = "wait"
    GOAL_WAIT = "goal wait"
