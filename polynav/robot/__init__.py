"""Robot backends behind one small interface: the simulator and, later, rosbridge."""
