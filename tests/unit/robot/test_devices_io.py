from __future__ import annotations

import pytest

from polynav.errors import InvalidRequest
from polynav.robot.sim.devices.io import SimIoPorts


def test_outputs_start_unset_and_keep_the_level_they_are_set_to() -> None:
    bank = SimIoPorts("base", outputs=3, first_output=1)
    assert bank.outputs() == [None, None, None]
    bank.set_output(2, 1)
    bank.set_output(3, 0)
    assert bank.outputs() == [None, 1, 0]


def test_a_looped_back_output_drives_its_input_and_inputs_read_what_is_wired_in() -> None:
    board = SimIoPorts("board", outputs=8, inputs=8, loopback={0: 7})
    assert board.inputs() == [0] * 8
    board.set_output(0, 1)
    board.set_input(3, 1)
    assert board.inputs() == [0, 0, 0, 1, 0, 0, 0, 1]


def test_pwm_and_servo_replace_a_plain_level_and_a_level_ends_them() -> None:
    module = SimIoPorts("voice", outputs=4, inputs=4, first_input=4)
    module.set_pwm(1, 1000, 75)
    assert module.pwm == {1: (1000, 75)} and module.outputs()[1] == 1
    module.set_servo(1, 90)
    assert module.pwm == {} and module.servo == {1: 90}
    module.set_output(1, 0)
    assert module.servo == {} and module.outputs()[1] == 0


@pytest.mark.parametrize(("call", "field"), [
    (lambda b: b.set_output(0, 1), "port"),
    (lambda b: b.set_output(4, 1), "port"),
    (lambda b: b.set_output(1, 2), "level"),
    (lambda b: b.set_input(3, 1), "port"),
    (lambda b: b.set_pwm(1, 0, 50), "freq"),
    (lambda b: b.set_pwm(1, 100, 101), "percent"),
    (lambda b: b.set_servo(1, 200), "angle"),
])
def test_bad_ports_and_levels_are_refused_and_change_nothing(call, field) -> None:  # type: ignore[no-untyped-def]
    bank = SimIoPorts("base", outputs=3, first_output=1, inputs=2, first_input=4)
    with pytest.raises(InvalidRequest) as err:
        call(bank)
    assert err.value.field == field
    assert bank.outputs() == [None, None, None] and bank.inputs() == [0, 0]
    assert bank.pwm == {} and bank.servo == {}
