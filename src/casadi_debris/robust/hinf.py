"""H-infinity controller synthesis by gamma bisection over fixed-gamma Riccati solves.

``control.hinfsyn`` starts SLICOT's own gamma search at 1e100 and can take
seconds, or fail, on D-scaled plants; a fixed-gamma solve (SB10AD, job 4)
takes milliseconds. A gamma counts as feasible when the solve succeeds and the
closed loop is stable; the controller returned is the smallest-norm controller met on the way.
"""

from __future__ import annotations

from dataclasses import dataclass

import control
import numpy as np
import scipy.linalg
import slycot
from slycot.exceptions import SlycotError

from casadi_debris.errors import SynthesisError

MAX_BISECTIONS = 60


@dataclass(frozen=True, eq=False)
class HinfResult:
    """Controller and closed loop at the best gamma found.

    Attributes
    ----------
    controller : control.StateSpace
        From the measurements to the controls.
    closed_loop : control.StateSpace
        From the exogenous inputs to the performance outputs.
    gamma : float
        Achieved closed-loop H-infinity norm.
    """

    controller: control.StateSpace
    closed_loop: control.StateSpace
    gamma: float


def well_conditioned(system: control.StateSpace) -> control.StateSpace:
    """Minimal, balanced realisation of a system (same transfer function).

    D-scaled plants carry poles from 1e-5 to 1e3 rad/s; their raw realisation
    (cond(A) ~ 1e24) makes every fixed-gamma Riccati solve fail, while the
    minimal realisation of SLICOT TB01PD followed by diagonal balancing solves.
    """
    minimal = control.minreal(system, verbose=False)
    if minimal.nstates == 0:
        return minimal
    _, (scale, _) = scipy.linalg.matrix_balance(minimal.A, permute=False, separate=True)
    return control.ss(
        minimal.A * (1.0 / scale)[:, None] * scale[None, :],
        minimal.B / scale[:, None],
        minimal.C * scale[None, :],
        minimal.D,
    )


def _solve_at(
    plant: control.StateSpace, n_measurements: int, n_controls: int, gamma: float
) -> HinfResult | None:
    """Central controller at a fixed gamma, or None if the Riccati solve fails or the loop is
    unstable."""
    n, m, p = plant.nstates, plant.ninputs, plant.noutputs
    try:
        out = slycot.sb10ad(
            n, m, p, n_controls, n_measurements, gamma, plant.A, plant.B, plant.C, plant.D, job=4
        )
    except (SlycotError, ValueError, np.linalg.LinAlgError):
        return None
    controller = control.ss(*out[1:5])
    closed_loop = control.ss(*out[5:9])
    if closed_loop.nstates and np.max(np.linalg.eigvals(closed_loop.A).real) >= 0:
        return None
    norm = float(control.linfnorm(closed_loop)[0])
    if not np.isfinite(norm):
        return None
    return HinfResult(controller, closed_loop, norm)


def hinf_synthesis(
    plant: control.StateSpace,
    n_measurements: int,
    n_controls: int,
    *,
    gamma_start: float = 1.0,
    tolerance: float = 0.01,
) -> HinfResult:
    """Smallest-gamma H-infinity controller, to a relative ``tolerance``.

    Parameters
    ----------
    plant : control.StateSpace
        Generalised plant; the last ``n_measurements`` outputs and
        ``n_controls`` inputs are the controller's.
    n_measurements, n_controls : int
    gamma_start : float
        First gamma tried; doubled until feasible.
    tolerance : float
        Relative width of the final bisection interval.

    Raises
    ------
    SynthesisError
        No stabilising controller up to gamma 1e8.
    """
    plant = well_conditioned(plant)
    upper = gamma_start
    best = _solve_at(plant, n_measurements, n_controls, upper)
    while best is None:
        upper *= 4.0
        if upper > 1e8:
            raise SynthesisError(
                "no stabilising H-infinity controller up to gamma 1e8 "
                "(check stabilisability/detectability of the generalised plant)"
            )
        best = _solve_at(plant, n_measurements, n_controls, upper)
    # Feasibility of a gamma is the solve succeeding with a stable loop; the
    # controller kept is the one with the smallest achieved norm (near the optimum
    # the central controller's norm can exceed the gamma it was built for).
    upper = min(upper, best.gamma)
    lower = 0.0
    for _ in range(MAX_BISECTIONS):
        if upper - lower <= tolerance * upper:
            break
        gamma = 0.5 * (lower + upper)
        trial = _solve_at(plant, n_measurements, n_controls, gamma)
        if trial is None:
            lower = gamma
            continue
        upper = gamma
        if trial.gamma < best.gamma:
            best = trial
    return best
