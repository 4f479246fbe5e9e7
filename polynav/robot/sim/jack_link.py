"""The simulated jacking axis and the world's carts, linked: raised under a cart the axis lifts
it, lowered it sets it down, whoever moves the axis (the runtime's dock, a Galileo
``jacking_move_to``). A real robot's jack lifts a real cart by itself; in the simulator this
link, stepped with the robot, stands in for the physics."""

from __future__ import annotations

from polynav.robot.profile import Payload
from polynav.robot.sim.carts import LIFT_HEIGHT
from polynav.robot.sim.devices.axis import SimAxis
from polynav.robot.sim.simulation import Simulation
from polynav.worlds.carts import CartKind


class JackLink:
    """Makes ``simulation``'s carts follow ``axis``; ``payload`` says what the jack lifts
    (None: the robot carries nothing, the jack stalls under any cart)."""

    def __init__(self, simulation: Simulation, axis: SimAxis, payload: Payload | None) -> None:
        self._sim = simulation
        self._axis = axis
        self._max_mass = payload.max_mass if payload is not None else None

    def follow(self, now: float) -> None:
        """Bring the axis to ``now`` and the cart on it to the axis's height."""
        sim, axis = self._sim, self._axis
        axis.advance(now)
        height = axis.true_position
        if sim.load is None:
            if height < LIFT_HEIGHT:
                return  # nothing held, nothing lifted: setting the height would do nothing
            under = sim.scene.carts.under(sim.name, sim.floor, sim.true_pose, CartKind.CART)
            if under is None or self._max_mass is None or under.spec.mass > self._max_mass:
                return  # nothing to lift, or too heavy: the jack stalls under it
        sim.set_jack_height(height)
