"""Textbook generalised plants for mu-synthesis, to check the D-K iteration against.

Skogestad and Postlethwaite, *Multivariable Feedback Control: Analysis and
Design*, 2nd ed., Wiley 2005, section 8.12.4 (the DK-iteration example,
Table 8.1): the distillation column in LV configuration with input gain
uncertainty and a performance weight on the sensitivity.
"""

from __future__ import annotations

import control
import numpy as np
import scipy.linalg

from casadi_debris.robust.plant import static_gain

DISTILLATION_GAIN = np.array([[87.8, -86.4], [108.2, -109.6]])
DISTILLATION_BLOCKS = (("complex", 1), ("complex", 1), ("complex", 2))


def distillation_column() -> control.StateSpace:
    """The distillation column's generalised plant for robust performance.

    G(s) = DISTILLATION_GAIN / (75 s + 1) (min^-1), input uncertainty
    W_I(s) = (s + 0.2) / (0.5 s + 1) I2, performance W_P(s) = (s / 2 + 0.05) /
    (s + 1e-6) I2 (the book's integrator moved to -1e-6 so that the plant is
    stabilisable). With y_delta the uncertainty's output, w the disturbance and
    u the control::

        z_delta = W_I u,   v = G (u + y_delta) + w,   z_p = W_P v,   y = -v

    Inputs [y_delta (2), w (2), u (2)], outputs [z_delta (2), z_p (2), y (2)];
    the structure is two complex scalars (the diagonal input uncertainty) and a
    full 2 x 2 performance block (:data:`DISTILLATION_BLOCKS`).

    Returns
    -------
    control.StateSpace
        6 states, 6 inputs, 6 outputs.
    """
    lag = control.ss([[-1.0 / 75.0]], [[1.0]], [[1.0 / 75.0]], [[0.0]])
    plant = control.append(lag, lag) * static_gain(DISTILLATION_GAIN)
    performance = control.ss(control.tf([0.5, 0.05], [1.0, 1e-6]))
    uncertainty = control.ss(control.tf([1.0, 0.2], [0.5, 1.0]))
    eye, zero = np.eye(2), np.zeros((2, 2))
    v = plant * static_gain(np.hstack([eye, zero, eye])) + static_gain(np.hstack([zero, eye, zero]))
    outputs = [
        control.append(uncertainty, uncertainty) * static_gain(np.hstack([zero, zero, eye])),
        control.append(performance, performance) * v,
        -v,
    ]
    return control.ss(
        scipy.linalg.block_diag(*[o.A for o in outputs]),
        np.vstack([o.B for o in outputs]),
        scipy.linalg.block_diag(*[o.C for o in outputs]),
        np.vstack([o.D for o in outputs]),
    )
