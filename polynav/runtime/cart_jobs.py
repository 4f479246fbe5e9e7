"""The bookkeeping of :mod:`polynav.runtime.cart_commands`: a dock's or leave's phases and
state, what the robot carries, and the navigation stack's configuration while it carries it."""

from __future__ import annotations

import enum
from collections.abc import Callable
from dataclasses import dataclass, replace

from polynav.geometry import Pose2D
from polynav.nav.stack import StackConfig
from polynav.robot.profile import RobotProfile
from polynav.runtime.cart_events import CartFailure
from polynav.worlds.carts import WorldCart, carried_footprint


class Phase(enum.Enum):
    """Where a dock (going, seeing, entering, taking) or a leave (carrying, releasing,
    exiting) stands; a failed dock's try backs out (exiting) before its retry."""

    GOING = "going"
    SEEING = "seeing"
    ENTERING = "entering"
    TAKING = "taking"
    CARRYING = "carrying"
    RELEASING = "releasing"
    EXITING = "exiting"


@dataclass(slots=True)
class CartJob:
    """One dock or leave under way: its load, phase and try, and what its phase follows."""

    action: str  # "dock" or "leave"
    cart: WorldCart
    phase: Phase
    attempt: int = 1
    goal_id: int | None = None
    since: float = 0.0
    target: Pose2D | None = None  # the load's pose as seen (map frame)
    scans: int = 0
    last_scan: float = -1.0
    progress: float = 0.0  # odometry distance covered in this phase
    progress_at: float = 0.0
    start_odometry: Pose2D | None = None
    cabin_id: str | None = None
    then: Callable[[], None] | None = None  # after a successful leave
    number: int = 0  # which dock or leave of the runtime's it is
    failure: tuple[CartFailure, str] | None = None  # a try failed: back out, then retry


@dataclass(frozen=True, slots=True)
class Load:
    """What the robot carries: the load and where it sits in the robot's frame."""

    cart: WorldCart
    offset: Pose2D


def loaded_config(config: StackConfig, profile: RobotProfile, load: Load | None) -> StackConfig:
    """``config`` for ``profile``'s robot carrying ``load``: the carried footprint (the hull of
    body and load) in the costmap and the controller's checks, the profile's loaded speeds and
    acceleration; unchanged when it carries nothing (or its profile has no payload)."""
    payload = profile.payload
    if load is None or payload is None:
        return config
    c = load.cart
    body = carried_footprint(profile.footprint, load.offset, c.length, c.width, c.leg_radius)
    ctl = config.controller
    v = min(ctl.max_linear_velocity, payload.linear_velocity)
    w = min(ctl.max_angular_velocity, payload.angular_velocity)
    controller = replace(
        ctl, max_linear_velocity=v, max_angular_velocity=w,
        linear_acceleration=min(ctl.linear_acceleration, payload.linear_acceleration),
        min_regulated_speed=min(ctl.min_regulated_speed, v),
        min_approach_velocity=min(ctl.min_approach_velocity, v),
        min_rotation_speed=min(ctl.min_rotation_speed, w))
    cm = config.costmap
    costmap = replace(cm, robot_radius=max(cm.robot_radius, body.inscribed_radius),
                      inscribed_cell_margin=0.0,
                      inflation_radius=max(cm.inflation_radius,
                                           body.circumscribed_radius + 0.05))
    return replace(config, controller=controller, costmap=costmap, footprint=body)
