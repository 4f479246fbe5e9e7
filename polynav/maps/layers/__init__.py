"""The costmap's layers, one module each (Lu et al., IROS 2014; Nav2 ``costmap_2d``).

Each layer keeps its own state and implements :class:`polynav.maps.interface.CostmapLayer`:
``update_bounds`` reports the cells it changed since it was last asked, then ``update_costs``
writes into the master grid inside the union window only. :mod:`polynav.maps.costmap` composes
them in the order static, keepout, obstacle, inflation; :mod:`.window` holds the window
arithmetic they share.
"""
