"""Multi-start time-optimal slews at thruster level.

The thruster-level OCP (thrust per engine as the control) has the same local
optima as the torque-level one and more: the engines' torque set is a
polytope, not a box. Started from the eigenaxis bang-bang alone, IPOPT keeps
the eigenaxis's structure. So the solve here starts from:

- the eigenaxis bang-bang (the least-fuel thrust of its torque);
- the torque box's own time-optimal slew, searched globally
  (:func:`~casadi_debris.slews._global_slew.global_time_optimal`), its torque
  turned into the least-fuel thrust that comes closest (the box's corners lie
  outside the engines' set, so this guess is only near-feasible);
- seeded perturbations of both (thrust times 1 + noise, length scaled).

Each start is the same NLP (:func:`~casadi_debris.slews._transcription.transcribe_and_solve`);
they run in parallel processes (:func:`~casadi_debris.parallel.parallel_map`),
each building the OCP once. The best converged one is kept; the report gives
every start's duration, how many reached the best, the distinct local optima
and the torque box's optimum beside them, and a ``logging`` warning says when
the starts disagree. The search is global in practice only: nothing proves
that no start would do better.
"""

from __future__ import annotations

import dataclasses
import functools
import logging
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from casadi_debris.slews._global_slew import GlobalSlew, SearchSettings, global_time_optimal
from casadi_debris.slews._initial_guess import InitialGuess, shaped_guess
from casadi_debris.slews._multistart import AGREEMENT_TOLERANCE, distinct, solve_each
from casadi_debris.slews._ocp_problem import SlewOcp
from casadi_debris.slews._propellant import least_fuel_thrust
from casadi_debris.slews._rigid_body import RigidBody
from casadi_debris.slews._transcription import (
    Horizon,
    NlpSolution,
    SlewNotConvergedError,
    transcribe_and_solve,
)

logger = logging.getLogger(__name__)

# A thruster-level solve costs 10-50 torque-level starts; four starts cover the two
# structures (eigenaxis, box optimum) and one perturbation of each.
MAX_THRUSTER_STARTS = 4
GUESS_SUBDIVISION = 4  # guess samples per collocation interval
NOISE = 0.3
LENGTH_SPREAD = (0.97, 1.03)


@dataclass(frozen=True)
class ThrusterStart:
    """One initial guess: thrust held on knots (picklable).

    Attributes
    ----------
    label : str
    knots_s : ndarray, shape (K + 1,)
        Segment bounds, s, from 0.
    thrust_N : ndarray, shape (K, n_engines)
        Thrust held on each segment, N.
    peak_rate_rad_s : float
        Scale of the rates (the eigenaxis bang-bang's peak).
    """

    label: str
    knots_s: np.ndarray
    thrust_N: np.ndarray
    peak_rate_rad_s: float

    def guess(self) -> InitialGuess:
        """The start as the transcription's guess."""
        return shaped_guess(self.knots_s, self.thrust_N, self.peak_rate_rad_s)


@dataclass(frozen=True)
class ThrusterOutcome:
    """Where IPOPT went from one start (``solution`` None unless it converged)."""

    label: str
    status: str
    duration_s: float
    solution: NlpSolution | None


def _context(problem: Any, target: Any, options: Any) -> SlewOcp:
    return SlewOcp(problem, target, options)


def _solve(intervals: int, ocp: SlewOcp, start: ThrusterStart) -> ThrusterOutcome:
    solution = transcribe_and_solve(
        ocp, fuel=False, horizon=Horizon(None, intervals), guess=start.guess()
    )
    return ThrusterOutcome(start.label, solution.status, float(solution.knots_s[-1]), solution)


def thruster_starts(
    ocp: SlewOcp, eigenaxis: InitialGuess, box: GlobalSlew, count: int, seed: int
) -> list[ThrusterStart]:
    """``count`` starts (module notes), the random ones drawn from ``default_rng(seed)``."""
    intervals = (ocp.options.intervals or 40) * GUESS_SUBDIVISION
    knots = np.linspace(0.0, eigenaxis.total_s, intervals + 1)
    eigen_thrust = eigenaxis.controls(0.5 * (knots[:-1] + knots[1:]))
    # At zero net force the guesses hold it too: a guess off that plane cost IPOPT most
    # of its time getting back to it.
    box_thrust = least_fuel_thrust(
        ocp.geometry, box.torque_Nm, zero_net_force=ocp.options.zero_net_force
    )[0]
    peak = eigenaxis.peak_rate_rad_s
    bases = [
        ThrusterStart("eigenaxis", knots, eigen_thrust, peak),
        ThrusterStart("torque-box optimum", box.knots_s, box_thrust, peak),
    ]
    upper = ocp.options.torque_fraction * ocp.f_max
    rng = np.random.default_rng(seed)
    starts = list(bases)
    for index in range(count - len(bases)):
        base = bases[index % len(bases)]
        noisy = base.thrust_N * (1.0 + NOISE * rng.standard_normal(base.thrust_N.shape))
        stretched = base.knots_s * rng.uniform(*LENGTH_SPREAD)
        label = f"perturbed {base.label} {index + 1}"
        starts.append(ThrusterStart(label, stretched, np.clip(noisy, 0.0, upper), peak))
    return starts[:count]


def thruster_time_optimal(
    ocp: SlewOcp, eigenaxis: InitialGuess, settings: SearchSettings
) -> tuple[NlpSolution, dict[str, Any]]:
    """The time-optimal thruster-level slew of ``ocp`` from several starts.

    Parameters
    ----------
    ocp : SlewOcp
        At thruster level (``ocp.options.thrusters``).
    eigenaxis : InitialGuess
        The eigenaxis bang-bang as thrust
        (:func:`~casadi_debris.slews._initial_guess.bang_bang_guess`).
    settings : SearchSettings
        Intervals, seed, workers; ``settings.starts`` capped at ``MAX_THRUSTER_STARTS``
        here (the torque box's own search takes all of them).

    Returns
    -------
    solution : NlpSolution
        The best converged start's.
    report : dict
        Figures for the profile's settings (s), units in the keys.

    Raises
    ------
    SlewNotConvergedError
        No start converged.
    """
    box = global_time_optimal(RigidBody(ocp.inertia, ocp.upper, ocp.lower), ocp.target, settings)
    count = max(1, min(settings.starts, MAX_THRUSTER_STARTS))
    starts = thruster_starts(ocp, eigenaxis, box, count, settings.seed)
    workers = dataclasses.replace(settings, starts=count).processes()
    outcomes = _run(ocp, starts, settings.intervals, workers)
    converged = [o for o in outcomes if o.solution is not None]
    if not converged:
        statuses = ", ".join(sorted({o.status for o in outcomes}))
        raise SlewNotConvergedError(
            f"thruster-level slew did not converge from any of {count} starts (ipopt: {statuses})"
        )
    best = min(converged, key=lambda o: o.duration_s)
    return _solution_of(best), _report(outcomes, best, box, workers)


def _solution_of(outcome: ThrusterOutcome) -> NlpSolution:
    if outcome.solution is None:
        raise SlewNotConvergedError(f"start {outcome.label}: {outcome.status}")
    return outcome.solution


def _run(
    ocp: SlewOcp, starts: list[ThrusterStart], intervals: int, workers: int
) -> list[ThrusterOutcome]:
    return solve_each(
        functools.partial(_solve, intervals),
        starts,
        functools.partial(_context, ocp.problem, ocp.target, ocp.options),
        workers,
        lambda start, error: ThrusterOutcome(start.label, error, math.nan, None),
    )


def _report(
    outcomes: list[ThrusterOutcome], best: ThrusterOutcome, box: GlobalSlew, workers: int
) -> dict[str, Any]:
    target = best.duration_s
    converged = [o for o in outcomes if o.solution is not None]
    agreeing = sum(
        1 for o in converged if abs(o.duration_s - target) <= AGREEMENT_TOLERANCE * target
    )
    count = len(outcomes)
    report = {
        "starts": count,
        "starts_converged": len(converged),
        "starts_agreeing": agreeing,
        "agreement_fraction": agreeing / count,
        "best_start": best.label,
        "start_durations_s": {o.label: o.duration_s for o in outcomes},
        "local_optima_s": list(distinct([o.duration_s for o in converged])),
        "workers": workers,
        "torque_box_duration_s": box.duration_s,
        "torque_box_agreement_fraction": box.report["agreement_fraction"],
    }
    if agreeing < count:
        logger.warning(
            "thruster-level time-optimal slew: %d of %d starts reach the best, %.6g s "
            "(other local optima: %s s): the best found may not be the global optimum",
            agreeing,
            count,
            target,
            ", ".join(f"{v:.6g}" for v in report["local_optima_s"][1:]) or "none",
        )
    return report
