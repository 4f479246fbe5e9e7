"""The simulator's peripherals: one module per device, each advanced on the runtime's clock.

:func:`simulated_devices` builds the :class:`~polynav.robot.devices.DeviceSet` of a simulated
robot: a slide table, a jacking lift with a turntable, environment and air sensors, a speaker,
the chassis buzzer, three IO banks (the base's outputs, an 8-in/8-out expansion board, the
voice module's 4+4), the camera and a PTZ network camera that render from the lidar, the
calibration procedures and a software updater with nothing to update to. Storage that any
backend needs alike (voice packages, photo and video folders) is in
:mod:`~polynav.robot.sim.devices.voice_library` and :mod:`~polynav.robot.sim.devices.media`.
"""

from __future__ import annotations

from collections.abc import Callable

from polynav.robot.devices import DeviceSet
from polynav.robot.interface import LaserScan
from polynav.robot.sim.devices.axis import AxisConfig, SimAxis
from polynav.robot.sim.devices.buzzer import SimBuzzer
from polynav.robot.sim.devices.calibration import (
    CameraCalibration,
    ImuCalibration,
    LidarCalibration,
)
from polynav.robot.sim.devices.camera import SimCamera
from polynav.robot.sim.devices.environment import SimEnvironmentSensors
from polynav.robot.sim.devices.io import SimIoPorts
from polynav.robot.sim.devices.onvif import SimPtzCamera
from polynav.robot.sim.devices.software_update import SimSoftwareUpdate
from polynav.robot.sim.devices.speaker import SimSpeaker

#: A slide table of 0.6 m and a jacking lift of 60 mm that stand part-way at power-on (they do
#: not know where until homed), and a turntable that turns freely.
SLIDE = AxisConfig("slide", travel=0.6, default_speed=0.05, homing_speed=0.03, max_speed=0.2,
                   start_position=0.17)
JACKING = AxisConfig("jacking", travel=0.06, default_speed=0.01, homing_speed=0.005,
                     max_speed=0.03, start_position=0.012)
JACKING_ROTATION = AxisConfig("jacking_rotation", travel=None, default_speed=0.5,
                              homing_speed=0.3, max_speed=1.5, start_position=0.4)


def simulated_devices(
    now: float, read_scan: Callable[[], LaserScan | None], *, seed: int = 0,
    version: str = "0.1.0",
) -> DeviceSet:
    """Simulated peripherals started at ``now``; the cameras render from ``read_scan`` (the
    robot's lidar: the simulator's, or a real one's for a bridged robot with no devices wired)."""
    camera_calibration = CameraCalibration()
    return DeviceSet(
        slide=SimAxis(SLIDE, now),
        jacking=SimAxis(JACKING, now),
        jacking_rotation=SimAxis(JACKING_ROTATION, now),
        sensors=SimEnvironmentSensors(seed, now),
        speaker=SimSpeaker(),
        buzzer=SimBuzzer(),
        io=SimIoPorts("the base's IO", outputs=3, first_output=1),
        expansion_io=SimIoPorts("the expansion board", outputs=8, inputs=8),
        voice_io=SimIoPorts("the voice module", outputs=4, inputs=4, first_input=4),
        camera=SimCamera(read_scan),
        ptz_camera=SimPtzCamera(read_scan),
        camera_calibration=camera_calibration,
        lidar_calibration=LidarCalibration(camera_calibration),
        imu_calibration=ImuCalibration(),
        software_update=SimSoftwareUpdate(version),
    )
