"""ROS 1 messages in their JSON form (rosbridge, Galileo's WebSocket): polynav's readings
written as ROS messages, and ROS messages read back, with the field names, nesting and key order
of the ``.msg`` definitions. Pure functions; every wire that speaks ROS uses these, so a
LaserScan is written one way only."""
