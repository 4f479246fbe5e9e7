"""The fleet manager: missions queued in the fleet's records and dispatched to the robots,
orders re-sent until confirmed, leases decided by the records (:mod:`.manager`)."""

from polynav.fleet.manager.dispatch import Candidate, DispatchConfig, Target, choose
from polynav.fleet.manager.manager import FleetManager
from polynav.fleet.manager.values import FleetEvent, FleetManagerConfig, RobotView, SitePoints

__all__ = [
    "Candidate",
    "DispatchConfig",
    "FleetEvent",
    "FleetManager",
    "FleetManagerConfig",
    "RobotView",
    "SitePoints",
    "Target",
    "choose",
]
