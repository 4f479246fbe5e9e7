"""The runtime: one robot's clock, backend and services, advanced together.

- :mod:`~polynav.runtime.robot_runtime`: :class:`RobotRuntime` (modes, commands, the tick loop);
- :mod:`~polynav.runtime.events` and :mod:`~polynav.runtime.event_bus`: typed events and their
  non-blocking fan-out to adapters;
- :mod:`~polynav.runtime.status`: the status snapshot adapters read;
- :mod:`~polynav.runtime.settings`: operator settings with their ranges;
- :mod:`~polynav.runtime.teleop` (dead-man) and :mod:`~polynav.runtime.local_move` (rotate,
  drive a distance): the motions the runtime commands itself;
- :mod:`~polynav.runtime.sim_driver`: the stack on the simulator without a runtime (scenario
  tests, the bench).
"""
