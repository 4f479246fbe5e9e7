"""Docking by what the robot sees: the charger's front plate, its shape, and finding it in a scan.

:mod:`~polynav.docking.shape` describes the plate (a flat face with a V notch) in the dock's own
frame; :mod:`~polynav.docking.detector` finds that shape among a scan's points near where the
site's marker says the charger is, and returns the charger's pose as seen. The simulator builds
its charger bodies from the same shape, and the navigator's dock phase drives onto the pose the
detector returns (:mod:`~polynav.nav.charger_phases`).
"""
