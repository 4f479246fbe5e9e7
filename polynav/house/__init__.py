"""The house: how a site's processes are put together.

``polynav run --robots N`` builds a :class:`~polynav.house.building.Building` (one simulated
world, N robot runtimes, their VDA 5050 vehicles and the fleet's master control, on one loop)
and serves each robot's APIs (:mod:`polynav.house.serve`). Composition lives here, above every
layer it wires, so that :mod:`polynav.fleet` holds only what a fleet manager and a vehicle run
and no layer below imports upward.
"""
