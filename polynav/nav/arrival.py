"""Is an arrival good enough to call succeeded? The localization's word on where the robot is.

The controller stops when the *estimate* is on the goal. Where the scan pins the pose that is
where the robot is, to a centimetre; in an open square beyond the lidar's range it is dead
reckoning, tens of centimetres off after a few tens of metres, and the estimate cannot tell. The
localization's :class:`~polynav.localization.interface.PoseUncertainty` can: every arrival
records it on the attempt (and so on the success event and in the status), and a goal that asks
for a precise arrival (:attr:`~polynav.nav.attempt.GoalOptions.max_position_uncertainty`, docking
by default) fails ``not localized`` instead of succeeding off the point.
"""

from __future__ import annotations

from dataclasses import dataclass

from polynav.localization.interface import LocalizationEstimate, LocalizationState
from polynav.nav.attempt import GoalOptions


@dataclass(frozen=True, slots=True)
class Verdict:
    """``ok``: the arrival stands; else ``message`` says why the pose cannot be trusted."""

    ok: bool
    message: str = ""


def judge(options: GoalOptions, estimate: LocalizationEstimate | None) -> Verdict:
    """Whether ``estimate`` at arrival meets what ``options`` demand of its precision.

    Args:
        options: the goal's options (its ``required_position_uncertainty``).
        estimate: the localization estimate the controller arrived on (``None``: not known).

    Returns:
        ``Verdict(True)`` when the goal demands nothing or the pose is known well enough.
    """
    required = options.required_position_uncertainty
    if required is None:
        return Verdict(True)
    if estimate is None or estimate.state is not LocalizationState.TRACKING:
        state = "unknown" if estimate is None else estimate.state.value
        return Verdict(False, f"localization is {state} at the goal")
    if estimate.uncertainty is None:
        return Verdict(False, "the localization gives no uncertainty at the goal")
    position = estimate.uncertainty.position
    if position > required:
        return Verdict(False, f"position known to {position:.3f} m at the goal, "
                              f"{required:.3f} m required")
    return Verdict(True)
