"""The action types, registered by wire name in :data:`polynav.tasks.action.ACTIONS` on
import."""

from polynav.tasks.actions import charging, devices, motion, navigation, waiting

__all__ = ["charging", "devices", "motion", "navigation", "waiting"]
