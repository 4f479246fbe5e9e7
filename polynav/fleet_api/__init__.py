"""The fleet manager's REST + WebSocket API (``polynav fleet``): an adapter of
:class:`~polynav.fleet.manager.FleetManager`, as :mod:`polynav.api` is of one robot."""

from polynav.fleet_api.app import FleetApiConfig, create_app

__all__ = ["FleetApiConfig", "create_app"]
