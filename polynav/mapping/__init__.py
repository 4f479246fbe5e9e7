"""Mapping: 2-D lidar SLAM (submaps, pose graph, loop closure), log readers and evaluation."""
