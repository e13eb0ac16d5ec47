"""The closed loop of a controller around the real-parametric plant, with the performance channels.

Signals as in :mod:`casadi_debris.robust.plant` (deg and mNm), with
the parametric plant's real channels in place of the complex uncertainty
block::

    plant input  up = u + Vd w_d
    [q; y]          = P_lft [w; up]        (w = z q per real block)
    e               = Vr w_e - y,   u = K e    (Vr: the reference scaling, Ve by default)
    z_e             = We Ve^-1 e,   z_u = Wu Vu^-1 u

The closed loop maps [w; w_e; w_d] to [q; z_e; z_u]. Robust stability is mu
of its (q, w) part over the real blocks; robust performance is mu of the
whole over the real blocks and one full complex 6 x 6 block.
"""

from __future__ import annotations

import control
import numpy as np

from casadi_debris.robust.mu._lft import ParametricPlant
from casadi_debris.robust.plant import PerformanceWeights, named, signals, static_gain

N_PERFORMANCE = 6


def _parts(plant: ParametricPlant, weights: PerformanceWeights) -> list[control.StateSpace]:
    """The plant, weights and junctions, every one but the controller."""
    error_weight = weights.error * static_gain(np.linalg.inv(weights.error_scaling))
    effort_weight = weights.control_effort * static_gain(np.linalg.inv(weights.control_scaling))
    return [
        plant.system(),
        named(error_weight, "e", "z_e", "We"),
        named(effort_weight, "u", "z_u", "Wu"),
        named(static_gain(weights.disturbance_scaling), "w_d", "d", "Vd"),
        named(static_gain(weights.reference), "w_e", "r", "Vr"),
        control.summing_junction(["u", "d"], "up", dimension=3, name="plant_input"),
        control.summing_junction(["r", "-y"], "e", dimension=3, name="error"),
    ]


def parametric_closed_loop(
    plant: ParametricPlant, controller: control.StateSpace, weights: PerformanceWeights
) -> control.StateSpace:
    """Closed loop [w; w_e; w_d] -> [q; z_e; z_u] of ``controller`` around ``plant``.

    Parameters
    ----------
    plant : ParametricPlant
        In design units (torque mNm, attitude deg).
    controller : control.StateSpace
        Attitude error [deg] -> torque [mNm], u = K e.
    weights : PerformanceWeights

    Returns
    -------
    control.StateSpace
        ``plant.n_real + 6`` inputs and outputs.
    """
    r = plant.n_real
    parts = [*_parts(plant, weights), named(controller, "e", "u", "K")]
    inputs = signals("w", r) + signals("w_e", 3) + signals("w_d", 3)
    outputs = signals("q", r) + signals("z_e", 3) + signals("z_u", 3)
    return control.interconnect(
        parts, inplist=inputs, outlist=outputs, inputs=inputs, outputs=outputs, name="closed_loop"
    )


def parametric_generalized_plant(
    plant: ParametricPlant, weights: PerformanceWeights
) -> control.StateSpace:
    """The generalised plant [w; w_e; w_d; u] -> [q; z_e; z_u; e] (the loop open at K).

    Parameters
    ----------
    plant : ParametricPlant
        In design units (torque mNm, attitude deg).
    weights : PerformanceWeights

    Returns
    -------
    control.StateSpace
        ``plant.n_real + 9`` inputs and outputs, the controller's three last.
    """
    r = plant.n_real
    inputs = signals("w", r) + signals("w_e", 3) + signals("w_d", 3) + signals("u", 3)
    outputs = signals("q", r) + signals("z_e", 3) + signals("z_u", 3) + signals("e", 3)
    return control.interconnect(
        _parts(plant, weights),
        inplist=inputs,
        outlist=outputs,
        inputs=inputs,
        outputs=outputs,
        name="parametric_plant",
    )
