"""Costmap cell values, named once, with Nav2's numbers so a polynav costmap reads the same in ROS.

0 is free; 1..252 are inflation costs that fall off with distance from an obstacle; 253 means the
robot's footprint centred here would touch an obstacle; 254 is an obstacle; 255 is unknown.
"""

from __future__ import annotations

FREE = 0
INSCRIBED = 253
LETHAL = 254
UNKNOWN = 255

MAX_NON_OBSTACLE = 252
