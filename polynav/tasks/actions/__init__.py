"""The action types, registered by wire name in :data:`polynav.tasks.action.ACTIONS` on
import."""

from polynav.tasks.actions import (
    automation,
    axes,
    callback,
    carts,
    charging,
    devices,
    launch,
    lifts,
    media,
    motion,
    navigation,
    transfer,
    waiting,
)

__all__ = ["automation", "axes", "callback", "carts", "charging", "devices", "launch", "lifts",
           "media",
           "motion", "navigation", "transfer", "waiting"]
