"""Open-loop rigid-body runs, to check the dynamics against other simulators.

The rigid model (no array modes) with the problem's full rigid inertia
(hub, CubeSats and arrays), started at the identity attitude and at rest,
driven by a piecewise-constant torque: row k of the table is held from its
time to the next row's (the last row to the end). No disturbance, no
force. Integrated by CVODES on the model's ``dynamics`` Function with tight
tolerances, one integrator call per held segment.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from casadi_debris.config import Problem
from casadi_debris.dynamics import build_model
from casadi_debris.simulation._closed_loop import SimulationError

OPEN_LOOP_OPTIONS = {"abstol": 1e-13, "reltol": 1e-12, "max_num_steps": 1_000_000}
OUTPUT_SPACING_S = 1.0


@dataclass(frozen=True, eq=False)
class OpenLoopResult:
    """Rigid open-loop trajectory.

    Attributes
    ----------
    time_s : ndarray, shape (n,)
    quaternion_BN : ndarray, shape (n, 4)
        Scalar first.
    rate_rad_s : ndarray, shape (n, 3)
        omega_BN in B.
    torque_Nm : ndarray, shape (n, 3)
        Torque held from each instant on.
    inertia_kgm2 : ndarray, shape (3, 3)
    """

    time_s: np.ndarray
    quaternion_BN: np.ndarray
    rate_rad_s: np.ndarray
    torque_Nm: np.ndarray
    inertia_kgm2: np.ndarray


def open_loop_rigid(
    problem: Problem,
    knots_s: np.ndarray,
    torque_Nm: np.ndarray,
    duration_s: float | None = None,
) -> OpenLoopResult:
    """Integrate the rigid body under a held torque table.

    Parameters
    ----------
    problem : Problem
    knots_s : ndarray, shape (k,)
        Strictly increasing times [s], the first at 0.
    torque_Nm : ndarray, shape (k, 3)
        Torque in B held from each knot [N m].
    duration_s : float, optional
        End time; default the last knot (its torque is then never applied).

    Returns
    -------
    OpenLoopResult
        Sampled at the knots and every ``OUTPUT_SPACING_S`` in between.
    """
    knots = np.asarray(knots_s, dtype=float)
    torque = np.asarray(torque_Nm, dtype=float)
    if knots.ndim != 1 or len(knots) == 0 or torque.shape != (len(knots), 3):
        raise SimulationError(
            f"need k times and a (k, 3) torque table, got {knots.shape} and {torque.shape}"
        )
    if not (np.isfinite(knots).all() and np.isfinite(torque).all()):
        raise SimulationError("the torque table must be finite")
    if knots[0] != 0.0 or np.any(np.diff(knots) <= 0):
        raise SimulationError("times must start at 0 and increase strictly")
    end = float(knots[-1]) if duration_s is None else float(duration_s)
    if not end > 0:
        raise SimulationError(f"duration must be positive, got {end}")

    model = build_model(problem, modes=[])
    p = model.nominal_parameters
    x = ca.SX.sym("x", model.layout.size)
    tau = ca.SX.sym("tau", 3)
    h = ca.SX.sym("h")
    rate = model.dynamics(x, ca.vertcat(tau, ca.DM.zeros(6)), ca.DM(p))
    # Time scaled to one unit per segment, so one integrator serves every length h.
    dae = {"x": x, "p": ca.vertcat(tau, h), "ode": h * rate}
    step = ca.integrator("open_loop", "cvodes", dae, 0.0, 1.0, OPEN_LOOP_OPTIONS)

    grid = np.unique(
        np.concatenate([knots[knots < end], np.arange(0.0, end, OUTPUT_SPACING_S), [end]])
    )
    held = torque[np.clip(np.searchsorted(knots, grid, side="right") - 1, 0, len(knots) - 1)]
    states = np.zeros((len(grid), model.layout.size))
    states[0] = model.initial_state()
    for i in range(len(grid) - 1):
        params = np.append(held[i], grid[i + 1] - grid[i])
        states[i + 1] = np.asarray(step(x0=states[i], p=params)["xf"]).ravel()
    return OpenLoopResult(
        time_s=grid,
        quaternion_BN=states[:, model.layout.q],
        rate_rad_s=states[:, model.layout.omega],
        torque_Nm=held,
        inertia_kgm2=np.asarray(model.rigid_inertia(p)),
    )
