"""polynav: open indoor robot navigation that speaks the commercial robots' network dialects.

The package is layered (see DESIGN.md): ``geometry``, ``maps``, ``planning`` and ``control`` are
the pure core; ``localization`` and ``nav`` are services advanced on a clock; ``robot`` holds the
robot interface and its backends (the simulator first).
"""

__version__ = "0.1.0"
