"""The generalised plant of the four-block mixed-sensitivity problem with the
uncertainty channel (paper, Fig. 2 and eq. for z1, z2).

Signals (3 each, deg and mNm as in the paper's scalings)::

    plant input  up = u + Vd w_d + W w_delta      (input-multiplicative uncertainty)
    z_delta         = u + Vd w_d                  (what Delta sees)
    y               = star tracker(P_c up)        (measured attitude)
    e               = Vr w_e - y                  (tracking error, controller input)
    z_e             = We Ve^-1 e,   z_u = Wu Vu^-1 u

so that, with Delta = 0, [z_e; z_u] = diag(We Ve^-1, Wu Vu^-1) [S, -S P; K S, -K S P]
diag(Vr, Vd) [w_e; w_d]: the paper's four-block problem, whose Vr is its Ve (the
default of :class:`~casadi_debris.robust.plant.PerformanceWeights`). With Vr = Ve a
looser Ve also scales up the reference the loop must follow (the K S Ve block), so μ can
rise as Ve loosens; with Vr held, Ve scales only the error rows and μ cannot rise.
"""

from __future__ import annotations

from dataclasses import dataclass

import control
import numpy as np

from casadi_debris.robust.plant._weights import PerformanceWeights

N_CHANNELS = 3
INPUT_GROUPS = ("w_delta", "w_e", "w_d", "u")
OUTPUT_GROUPS = ("z_delta", "z_e", "z_u", "e")


def signals(name: str, count: int = N_CHANNELS) -> list[str]:
    """``name[0]`` .. ``name[count - 1]``: a vector signal's names for ``control.interconnect``."""
    return [f"{name}[{i}]" for i in range(count)]


def named(system: control.StateSpace, inputs: str, outputs: str, name: str) -> control.StateSpace:
    """``system`` with vector signals ``inputs[..]`` and ``outputs[..]``, called ``name``."""
    return control.ss(
        system.A,
        system.B,
        system.C,
        system.D,
        inputs=signals(inputs, system.ninputs),
        outputs=signals(outputs, system.noutputs),
        name=name,
    )


def static_gain(matrix: np.ndarray) -> control.StateSpace:
    """A memoryless system y = matrix u."""
    rows, cols = matrix.shape
    return control.ss(np.zeros((0, 0)), np.zeros((0, cols)), np.zeros((rows, 0)), matrix)


@dataclass(frozen=True, eq=False)
class GeneralizedPlant:
    """P with inputs [w_delta, w_e, w_d, u] and outputs [z_delta, z_e, z_u, e].

    Attributes
    ----------
    system : control.StateSpace
    blocks : tuple of int
        Sizes of the full complex blocks of the closed loop's structure:
        (3,) uncertainty, (6,) performance.
    n_measurements, n_controls : int
    """

    system: control.StateSpace
    blocks: tuple[int, ...] = (3, 6)
    n_measurements: int = N_CHANNELS
    n_controls: int = N_CHANNELS

    @property
    def n_exogenous(self) -> int:
        return sum(self.blocks)


def generalized_plant(
    plant: control.StateSpace, uncertainty_weight: control.StateSpace, weights: PerformanceWeights
) -> GeneralizedPlant:
    """Interconnect plant, sensor, weights and uncertainty channel.

    Parameters
    ----------
    plant : control.StateSpace
        Torque [mNm] to measured attitude [deg], star tracker included
        (``linearize(model, sensor=True, units="deg_mNm")``).
    uncertainty_weight : control.StateSpace
        Diagonal W, 3 x 3.
    weights : PerformanceWeights

    Returns
    -------
    GeneralizedPlant
    """
    error_weight = weights.error * static_gain(np.linalg.inv(weights.error_scaling))
    effort_weight = weights.control_effort * static_gain(np.linalg.inv(weights.control_scaling))
    parts = [
        named(plant, "up", "y", "plant"),
        named(uncertainty_weight, "w_delta", "w_out", "W"),
        named(error_weight, "e", "z_e", "We"),
        named(effort_weight, "u", "z_u", "Wu"),
        named(static_gain(weights.disturbance_scaling), "w_d", "d", "Vd"),
        named(static_gain(weights.reference), "w_e", "r", "Vr"),
        control.summing_junction(["u", "d"], "z_delta", dimension=N_CHANNELS, name="plant_input"),
        control.summing_junction(["z_delta", "w_out"], "up", dimension=N_CHANNELS, name="delta"),
        control.summing_junction(["r", "-y"], "e", dimension=N_CHANNELS, name="error"),
    ]
    inputs = [s for group in INPUT_GROUPS for s in signals(group)]
    outputs = [s for group in OUTPUT_GROUPS for s in signals(group)]
    system = control.interconnect(
        parts,
        inplist=inputs,
        outlist=outputs,
        inputs=inputs,
        outputs=outputs,
        name="generalized_plant",
    )
    return GeneralizedPlant(system)
