"""The time-optimal detumble transcribed in full: the body rates, step by step.

Euler's equations ``J omega' = tau - omega x J omega`` with a piecewise-constant
torque in the polytope ``{tau : N tau <= b}``, over a free final time ``T``,
direct multiple shooting (Runge-Kutta 4) and IPOPT: minimise ``T`` until
``|J omega(T)| <= h_end``. Tractable only for small tumbles, where the rates precess a
few times during the braking (at 1 rad/s they precess about once a second for two
days: a million steps); there it checks the averaged OCP
(:mod:`~casadi_debris.simulation.detumble._ocp`). IPOPT may return a local optimum;
it starts from the greedy law (the vertex that brakes ``|H|`` fastest each interval).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import casadi as ca
import numpy as np

from casadi_debris.errors import SimulationError
from casadi_debris.parallel import keep_ctrl_c
from casadi_debris.simulation.detumble._detumble import held_torque_rates

SUBSTEPS = 2
GREEDY_STEPS_PER_INTERVAL = 4
MAX_ITERATIONS = 3000


@dataclass(eq=False)
class FullDetumbleOcp:
    """Solution of the full transcription.

    Attributes
    ----------
    time_s : float
        Least time found (a local optimum).
    greedy_time_s : float
        The greedy law's time to ``h_end`` (sample-and-hold at the same intervals).
    rate_rad_s : ndarray, shape (n + 1, 3)
    torque_Nm : ndarray, shape (n, 3)
    solver_status : str
    wall_time_s : float
    """

    time_s: float
    greedy_time_s: float
    rate_rad_s: np.ndarray
    torque_Nm: np.ndarray
    solver_status: str
    wall_time_s: float


def full_time_optimal_detumble(
    inertia_kgm2: np.ndarray,
    normals: np.ndarray,
    offsets_Nm: np.ndarray,
    vertices_Nm: np.ndarray,
    initial_rate_rad_s: np.ndarray,
    final_momentum_Nms: float,
    *,
    n_intervals: int = 400,
) -> FullDetumbleOcp:
    """Minimise the time to bring ``|J omega|`` to ``final_momentum_Nms``.

    Parameters
    ----------
    inertia_kgm2 : ndarray, shape (3, 3)
    normals, offsets_Nm : ndarray, shapes (m, 3) and (m,)
        The torque polytope ``{tau : normals @ tau <= offsets}``, body axes.
    vertices_Nm : ndarray, shape (k, 3)
        Its vertices (for the greedy initial guess).
    initial_rate_rad_s : ndarray, shape (3,)
    final_momentum_Nms : float
    n_intervals : int
    """
    started = time.perf_counter()
    inertia = np.asarray(inertia_kgm2, dtype=float)
    rate0 = np.asarray(initial_rate_rad_s, dtype=float)
    guess_rates, guess_torque, greedy_s = _greedy_guess(
        inertia, np.asarray(vertices_Nm, float), rate0, final_momentum_Nms, n_intervals
    )
    opti = ca.Opti()
    rates = opti.variable(3, n_intervals + 1)
    unit_Nm = float(np.max(np.linalg.norm(vertices_Nm, axis=1)))
    torque = opti.variable(3, n_intervals)
    duration = opti.variable()
    step = _step(inertia)
    opti.subject_to(rates[:, 0] == rate0)
    for k in range(n_intervals):
        opti.subject_to(rates[:, k + 1] == step(rates[:, k], torque[:, k], duration / n_intervals))
    reach = ca.vec(ca.DM(normals) @ torque)
    opti.subject_to(reach <= ca.repmat(ca.DM(offsets_Nm), n_intervals, 1))
    final = ca.DM(inertia) @ rates[:, -1]
    # Scaled to one: IPOPT's constraint tolerance is absolute.
    opti.subject_to(ca.sumsqr(final) / final_momentum_Nms**2 <= 1.0)
    # No detumble beats the momentum bound; the greedy law is a feasible answer.
    travel = float(np.linalg.norm(inertia @ rate0)) - final_momentum_Nms
    opti.subject_to(opti.bounded(travel / unit_Nm, duration, 2.0 * greedy_s))
    opti.minimize(duration / greedy_s)
    opti.set_initial(rates, guess_rates.T)
    opti.set_initial(torque, guess_torque.T)
    opti.set_initial(duration, greedy_s)
    opti.solver(
        "ipopt", {"print_time": False}, {"print_level": 0, "max_iter": MAX_ITERATIONS, "sb": "yes"}
    )
    try:
        with keep_ctrl_c():
            solution = opti.solve()
    except RuntimeError as exc:
        raise SimulationError(
            f"full detumble OCP: IPOPT failed ({opti.stats()['return_status']})"
        ) from exc
    return FullDetumbleOcp(
        time_s=float(solution.value(duration)),
        greedy_time_s=greedy_s,
        rate_rad_s=np.asarray(solution.value(rates)).T,
        torque_Nm=np.asarray(solution.value(torque)).T,
        solver_status=str(solution.stats()["return_status"]),
        wall_time_s=time.perf_counter() - started,
    )


def _step(inertia: np.ndarray) -> ca.Function:
    """``omega, tau, dt -> omega(dt)`` under a held torque (Runge-Kutta 4)."""
    omega, tau, dt = ca.MX.sym("omega", 3), ca.MX.sym("tau", 3), ca.MX.sym("dt")
    after = held_torque_rates(inertia, omega, tau, dt, SUBSTEPS)
    return ca.Function("rate_step", [omega, tau, dt], [after])


def _greedy_guess(
    inertia: np.ndarray, vertices: np.ndarray, rate0: np.ndarray, h_end: float, n: int
) -> tuple[np.ndarray, np.ndarray, float]:
    """The greedy vertex law to ``|H| <= h_end``, then resampled on ``n`` equal intervals.

    Steps of ``|H_0| / (4 n max |tau|)``, shortened to a quarter of ``|H| / max |tau|``
    near the end so that a held vertex cannot overshoot the origin.
    """
    step = _step(inertia)
    brake = float(np.max(np.linalg.norm(vertices, axis=1)))
    longest = np.linalg.norm(inertia @ rate0) / brake / (n * GREEDY_STEPS_PER_INTERVAL)
    times: list[float] = [0.0]
    rates: list[np.ndarray] = [rate0]
    torques: list[np.ndarray] = []
    while (momentum := np.linalg.norm(inertia @ rates[-1])) > h_end:
        if len(torques) > 100 * n * GREEDY_STEPS_PER_INTERVAL:
            raise SimulationError("full detumble OCP: the greedy law does not brake this body")
        dt = float(min(longest, 0.25 * momentum / brake))
        tau = vertices[np.argmin(vertices @ (inertia @ rates[-1]))]
        rates.append(np.asarray(step(rates[-1], tau, dt), dtype=float).ravel())
        torques.append(tau)
        times.append(times[-1] + dt)
    greedy_s = times[-1]
    # The state at the last step at or before each node.
    index = np.searchsorted(times, np.linspace(0.0, greedy_s, n + 1), side="right") - 1
    held = np.array(torques)[np.minimum(index[:-1], len(torques) - 1)]
    return np.array(rates)[index], held, greedy_s
