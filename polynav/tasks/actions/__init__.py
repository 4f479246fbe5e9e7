"""The action types, registered by wire name in :data:`polynav.tasks.action.ACTIONS` on
import."""

from polynav.tasks.actions import devices, motion, navigation, transfer, waiting

__all__ = ["devices", "motion", "navigation", "transfer", "waiting"]
