"""Our own integration of a slew profile, independent of the slew module's check."""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from casadi_debris.config import Problem
from casadi_debris.model import Model, build_model


def final_state(problem: Problem, slew: Any, modes: str | list) -> tuple[Model, np.ndarray]:
    """The model (``build_model(problem, modes)``) and its state at the end of the slew,
    driven by the slew's input from rest by CVODES, restarting at every sample so that
    it never steps across a switch."""
    model = build_model(problem, modes)
    x = ca.SX.sym("x", model.layout.size)
    t = ca.SX.sym("t")
    ode = model.dynamics(x, slew.input_function(t), model.nominal_parameters)
    integrator = ca.integrator(
        "slew_check",
        "cvodes",
        {"x": x, "t": t, "ode": ode},
        0.0,
        np.asarray(slew.time_s),
        {"abstol": 1e-13, "reltol": 1e-11, "max_num_steps": 500000},
    )
    start = model.initial_state(slew.target.q_initial_BN)
    return model, np.array(integrator(x0=start)["xf"])[:, -1]
