"""Tasks: what the robot does with navigation over time (patrols over points, ...)."""
