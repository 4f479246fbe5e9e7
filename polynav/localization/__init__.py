"""Localization: odometry + IMU prediction corrected by scan-to-map matching."""
