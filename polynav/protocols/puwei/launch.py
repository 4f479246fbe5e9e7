"""``/api/roslaunch/...`` (puwei-api §5): the vendor's "programs" on the runtime's modes.

Mapping is the runtime's mapping mode; navigation/:name starts navigation on a saved map (A6:
the source mislabels it "start mapping"); stop ends whichever runs; status is 0 stopped, 1
mapping, 2 navigating. Starting one program while the other runs switches, as a roslaunch
does: mapping stops navigation first (navigating refuses while mapping: the map being built
would be lost, so the client must save and stop it). Stopping mapping saves the map once more
under the name ``map/save`` last used (the final optimisation of the whole map), else drops it.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

from polynav.errors import Conflict
from polynav.protocols.puwei.context import Context
from polynav.protocols.puwei.endpoint import RouteList
from polynav.protocols.puwei.request import PuweiRequest

log = logging.getLogger(__name__)

ROUTES = RouteList()

STOPPED, MAPPING, NAVIGATING = 0, 1, 2


@dataclass
class MappingState:
    """The name the map being built was last saved under (``map/save``)."""

    saved_as: str | None = None


def mapping_state(ctx: Context) -> MappingState:
    return ctx.state("puwei.mapping", MappingState)


def launch_status(ctx: Context) -> int:
    """0 stopped, 1 mapping, 2 navigating (loading a map to navigate on counts as 2)."""
    snap = ctx.runtime.status()
    if snap.mode == "mapping":
        return MAPPING
    if snap.mode == "navigating" or (snap.mode == "busy" and snap.map is not None):
        return NAVIGATING
    return STOPPED


@ROUTES.get("/api/roslaunch/mapping")
def start_mapping(ctx: Context, request: PuweiRequest) -> None:
    """Start a new map where the robot stands."""
    rt = ctx.runtime
    if rt.status().mode == "mapping":
        raise Conflict("mapping already runs: stop it first (GET /api/roslaunch/stop)")
    if rt.status().mode == "navigating":
        rt.stop_navigation()
    rt.start_mapping()
    mapping_state(ctx).saved_as = None
    log.info("puwei: mapping started")


@ROUTES.get("/api/roslaunch/navigation/:name")
def start_navigation(ctx: Context, request: PuweiRequest) -> None:
    """Navigate on saved map ``name`` (the robot localizes where it stands on it)."""
    name = request.name()
    if ctx.runtime.status().mode == "mapping":
        raise Conflict("mapping runs: save the map and stop mapping first")
    ctx.runtime.start_navigation(name)
    log.info("puwei: navigation started on map %s", name)


@ROUTES.get("/api/roslaunch/stop")
def stop(ctx: Context, request: PuweiRequest) -> None:
    """Stop mapping (saving under the last ``map/save`` name) or navigation; stopped: no-op."""
    rt = ctx.runtime
    mode = rt.status().mode
    if mode == "mapping":
        state = mapping_state(ctx)
        if state.saved_as is not None:
            rt.stop_mapping(state.saved_as, overwrite=True)
        else:
            rt.cancel_mapping()
        state.saved_as = None
    elif mode in ("navigating", "busy"):
        rt.stop_navigation()


@ROUTES.get("/api/roslaunch/status", inline=True)
def status(ctx: Context, request: PuweiRequest) -> int:
    """``data``: 0 stopped, 1 mapping, 2 navigating."""
    return launch_status(ctx)
