"""Global planning: grid A* and Theta* kernels, path post-processing, the grid planner wrapper."""
