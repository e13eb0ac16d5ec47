"""The disturbance torque the closed loop applies: the problem's sine plus its environment.

The sine (:attr:`~casadi_debris.dynamics.Model.disturbance`) acts as a function of
time inside the integrator. The environment torques the problem's
``[environment]`` switches on (:class:`~casadi_debris.environment.EnvironmentTorques`)
are evaluated once per control period, at its start, from the time, the
attitude of the state ``x`` (its rotation matrix, from the model's own
:func:`~casadi_debris.dynamics.rotation_matrix`), the rigid inertia of
the parameters ``p`` (the gravity gradient) and the arrays' angles of ``p``
(the faces the air and the light see), and held over the period like the
controller's torque. The arrays' deflection is left out of all three. With no
environment torque the step is the paper's, graph for graph.
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np

from casadi_debris.dynamics import Model, rotation_matrix
from casadi_debris.environment import EnvironmentTorques


def environment_function(model: Model) -> ca.Function | None:
    """``environment(t, x, p) -> tau`` [N m], the environment torques alone; None when off."""
    if not model.problem.environment.torques:
        return None
    t = ca.SX.sym("t")
    x = ca.SX.sym("x", model.layout.size)
    p = ca.SX.sym("p", len(model.parameter_names))
    layout = model.parameter_layout
    angles = [
        math.radians(array.angle_deg) + layout.array_angle_offset_rad(p, index)
        for index, array in enumerate(model.problem.arrays)
    ]
    dcm = rotation_matrix(x[model.layout.q])
    environment = EnvironmentTorques.of(model.problem, model.geometry)
    tau = environment.total(t, dcm, model.rigid_inertia(p), angles)
    return ca.Function("environment", [t, x, p], [tau], ["t", "x", "p"], ["tau"])


def disturbance_series(
    model: Model,
    time_s: np.ndarray,
    states: np.ndarray,
    parameters: np.ndarray,
    sine: np.ndarray | None = None,
) -> np.ndarray:
    """The disturbance at each instant, shape (n, 3) [N m].

    Parameters
    ----------
    time_s : ndarray, shape (n,)
    states : ndarray, shape (n, n_x)
        The plant's state at those instants.
    parameters : ndarray, shape (n_parameters,)
    sine : ndarray, shape (n, 3), optional
        The sine part at ``time_s``, when already known (:func:`sine_series`).
    """
    n = len(time_s)
    sine = sine_series(model, time_s) if sine is None else sine
    environment = environment_function(model)
    if environment is None:
        return sine
    p = np.broadcast_to(np.asarray(parameters, dtype=float)[:, None], (len(parameters), n))
    return sine + np.asarray(environment.map(n)(time_s, states.T, p)).T


def sine_series(model: Model, time_s: np.ndarray) -> np.ndarray:
    """The problem's sine disturbance at each instant, shape (n, 3) [N m]."""
    return np.asarray(model.disturbance.map(len(time_s))(time_s)).T
