"""The runtime: one robot's clock, backend and services, advanced together.

- :mod:`~polynav.runtime.robot_runtime`: :class:`RobotRuntime` (modes, commands, the control
  tick), the coordinator of the modules below;
- :mod:`~polynav.runtime.loop`: the loop thread, its pacing and the command queue;
- :mod:`~polynav.runtime.navigation_events`: navigator events as runtime events, with attempt
  ids unique for the runtime's lifetime;
- :mod:`~polynav.runtime.watchers`: e-stop, charge, low-battery and localization changes as
  events;
- :mod:`~polynav.runtime.sim_placement`: which simulated floor a map is on, and placing the
  simulated robot where the operator says it is;
- :mod:`~polynav.runtime.events` and :mod:`~polynav.runtime.event_bus`: typed events and their
  non-blocking fan-out to adapters;
- :mod:`~polynav.runtime.status`: the status snapshot adapters read;
- :mod:`~polynav.runtime.settings`: operator settings with their ranges;
- :mod:`~polynav.runtime.direct_motion`: the motions the runtime commands itself, teleop
  (:mod:`~polynav.runtime.teleop`, the dead-man) and local moves
  (:mod:`~polynav.runtime.local_move`, rotate or drive a distance);
- :mod:`~polynav.runtime.sim_driver`: the stack on the simulator without a runtime (scenario
  tests, the bench).
"""
