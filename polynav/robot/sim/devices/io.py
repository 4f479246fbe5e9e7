"""Simulated digital IO: the base's outputs, the IO expansion board and the voice module's IO.

A port bank has ``outputs`` (a level the robot drives, ``None`` until first set, as the built-in
ports report "not set") and ``inputs`` (levels the world drives: the simulator lets a test or
the demo wire a level in with :meth:`SimIoPorts.set_input`; unconnected inputs read low). An
output may be looped back to an input (``loopback``), as an integrator wires an expansion board
on the bench to check it.
"""

from __future__ import annotations

from collections.abc import Mapping

from polynav.errors import InvalidRequest


class SimIoPorts:
    """Implements :class:`~polynav.robot.devices.IoPorts`.

    Args:
        name: the bank's name, in error messages.
        outputs: how many outputs; ``first_output`` is the number of the first.
        inputs: how many inputs; ``first_input`` is the number of the first.
        loopback: output port -> input port it drives.
    """

    def __init__(
        self,
        name: str,
        *,
        outputs: int,
        inputs: int = 0,
        first_output: int = 0,
        first_input: int = 0,
        loopback: Mapping[int, int] | None = None,
    ) -> None:
        self.name = name
        self.first_output = first_output
        self.first_input = first_input
        self._outputs: list[int | None] = [None] * outputs
        self._inputs = [0] * inputs
        self._loopback = dict(loopback or {})
        self.pwm: dict[int, tuple[int, int]] = {}  # port -> (frequency [Hz], duty [%])
        self.servo: dict[int, int] = {}  # port -> angle [deg]

    def outputs(self) -> list[int | None]:
        return list(self._outputs)

    def inputs(self) -> list[int]:
        return list(self._inputs)

    @property
    def output_ports(self) -> range:
        return range(self.first_output, self.first_output + len(self._outputs))

    @property
    def input_ports(self) -> range:
        return range(self.first_input, self.first_input + len(self._inputs))

    def set_output(self, port: int, level: int) -> None:
        """Drive output ``port`` to ``level`` (a plain level ends PWM or servo on it).

        Raises:
            InvalidRequest: no such output, or a level other than 0 and 1.
        """
        index = self._output_index(port)
        if level not in (0, 1):
            raise InvalidRequest("level", f"must be 0 or 1, got {level!r}")
        self._outputs[index] = level
        self.pwm.pop(port, None)
        self.servo.pop(port, None)
        if port in self._loopback:
            self.set_input(self._loopback[port], level)

    def set_pwm(self, port: int, frequency: int, duty: int) -> None:
        """Raises: InvalidRequest: no such output, frequency not in 1..100000 Hz, duty not in
        0..100 %."""
        index = self._output_index(port)
        if not 1 <= frequency <= 100_000:
            raise InvalidRequest("freq", f"must be 1..100000 Hz, got {frequency}")
        if not 0 <= duty <= 100:
            raise InvalidRequest("percent", f"must be 0..100, got {duty}")
        self.servo.pop(port, None)
        self.pwm[port] = (frequency, duty)
        self._outputs[index] = 1 if duty >= 50 else 0  # the mean level a meter reads

    def set_servo(self, port: int, angle: int) -> None:
        """Raises: InvalidRequest: no such output, an angle outside 0..180 degrees."""
        self._output_index(port)
        if not 0 <= angle <= 180:
            raise InvalidRequest("angle", f"must be 0..180 degrees, got {angle}")
        self.pwm.pop(port, None)
        self.servo[port] = angle

    def set_input(self, port: int, level: int) -> None:
        """Wire ``level`` into input ``port`` (the simulated world's side).

        Raises:
            InvalidRequest: no such input, or a level other than 0 and 1.
        """
        if port not in self.input_ports:
            raise InvalidRequest("port", f"{self.name} has inputs {_span(self.input_ports)}, "
                                         f"not {port!r}")
        if level not in (0, 1):
            raise InvalidRequest("level", f"must be 0 or 1, got {level!r}")
        self._inputs[port - self.first_input] = level

    def _output_index(self, port: int) -> int:
        if port not in self.output_ports:
            raise InvalidRequest("port", f"{self.name} has outputs {_span(self.output_ports)}, "
                                         f"not {port!r}")
        return port - self.first_output


def _span(ports: range) -> str:
    return f"{ports.start}..{ports.stop - 1}" if len(ports) else "none"
