"""Time-optimal rest-to-rest slews of a rigid body that are global in practice.

The order of the solve:

1. multi-start collocation (:mod:`~casadi_debris.slews._multistart`): the
   eigenaxis bang-bang and seeded symmetry-breaking starts, in parallel;
2. symmetric images: the shortest few distinct optima mapped by the slew's
   (near) symmetries (half turns about body axes) and solved again, so that
   starts that went round the wrong way are not lost;
3. switch times (:mod:`~casadi_debris.slews._switch_times`): the best solution's
   bang-bang structure with its switch times as the decision variables, and the
   result verified by integrating the bang-bang control with CVODES.

A start *agrees* when its optimum, or one of its optimum's images, is the best
found; ``starts_agreeing_direct`` counts the starts whose own solve found it.
When a start ends elsewhere, or fails, a ``logging`` warning says so: the best
slew found may then not be the global one.

The result is a held torque on knots (s, N m), the same for a
:class:`~casadi_debris.slews._rigid_body.RigidBody` and for the torque-level
rigid slew of a problem, whose dynamics are the rigid body's
(:mod:`casadi_debris.slews._ocp_problem`: no force, so the translation stays at
rest), and a report for the profile's ``settings``.
"""

from __future__ import annotations

import logging
import math
import multiprocessing
import os
import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from casadi_debris.dynamics import attitude_error
from casadi_debris.slews._limits import axis_ratios, box_authority, box_check
from casadi_debris.slews._maneuver import (
    SlewTarget,
    eigenaxis_acceleration_limit,
    eigenaxis_duration_s,
    rigid_limit_duration,
)
from casadi_debris.slews._multistart import (
    AGREEMENT_TOLERANCE,
    MultiStartResult,
    RigidSlew,
    StartOutcome,
    distinct,
    make_starts,
    run_starts,
    symmetric_images,
)
from casadi_debris.slews._options import OptimalSlewSettings
from casadi_debris.slews._profile import (
    INTEGRATOR_OPTIONS,
    SlewProfile,
    sample_grid,
    zoh_input_function,
)
from casadi_debris.slews._rigid_body import N_RIGID_STATE, RigidBody, scaled_rigid_ode
from casadi_debris.slews._switch_times import NotBangBangError, refine, switch_structure

logger = logging.getLogger(__name__)
# Below this many starts a second process costs more than it saves.
PARALLEL_STARTS = 4
# The shortest distinct optima whose symmetric images are solved.
IMAGED_OPTIMA = 3
# Segments shorter than this (scaled time) are dropped from the refined profile.
MIN_SEGMENT = 1e-12


@dataclass(frozen=True)
class GlobalSlew:
    """The best time-optimal slew found, as a held torque.

    Attributes
    ----------
    knots_s : ndarray, shape (K + 1,)
        Segment bounds, s, from 0.
    torque_Nm : ndarray, shape (K, 3)
        Torque held on each segment, N m.
    status : str
        IPOPT's status on the solve the profile comes from.
    limit_duration_s : float
        The eigenaxis limit, s.
    report : dict
        The multi-start and refinement figures, units in the keys (module notes).
    """

    knots_s: np.ndarray
    torque_Nm: np.ndarray
    status: str
    limit_duration_s: float
    report: dict[str, Any]

    @property
    def duration_s(self) -> float:
        """Length of the slew, s."""
        return float(self.knots_s[-1])


@dataclass(frozen=True)
class SearchSettings:
    """How hard the time-optimal slew is searched.

    Attributes
    ----------
    intervals : int
        Collocation intervals of every start.
    starts : int
        How many starts.
    seed : int
        Seed of the random starts.
    workers : int or None
        Processes; None: two when there are at least ``PARALLEL_STARTS`` starts,
        this is the main process and the machine has two cores.
    refine : bool
        Refine the best solution's switch times.
    """

    intervals: int
    starts: int
    seed: int
    workers: int | None
    refine: bool

    def processes(self) -> int:
        """The worker processes to use."""
        if self.workers is not None:
            return self.workers
        main = multiprocessing.parent_process() is None
        cores = os.cpu_count() or 1
        return 2 if main and cores >= 2 and self.starts >= PARALLEL_STARTS else 1


def search_settings(options: OptimalSlewSettings, intervals: int) -> SearchSettings:
    """The search of ``options`` (starts, seed, workers, refine) on ``intervals``."""
    return SearchSettings(intervals, options.starts, options.seed, options.workers, options.refine)


def rigid_slew(body: RigidBody, target: SlewTarget, intervals: int) -> RigidSlew:
    """The slew of ``body`` to ``target`` with the scales of its eigenaxis limit."""
    alpha = eigenaxis_acceleration_limit(
        body.inertia_kgm2, target.axis_B, body.lower_Nm, body.upper_Nm
    )
    return RigidSlew(
        body=body,
        q_initial_BN=target.q_initial_BN,
        q_final_BN=target.q_final_BN,
        axis_B=target.axis_B,
        angle_rad=target.angle_rad,
        time_scale_s=rigid_limit_duration(target.angle_rad, alpha),
        alpha_max_rad_s2=alpha,
        intervals=intervals,
    )


def global_time_optimal(
    body: RigidBody, target: SlewTarget, settings: SearchSettings
) -> GlobalSlew:
    """The time-optimal rest-to-rest slew of ``body``, global in practice (module notes).

    Parameters
    ----------
    body : RigidBody
        Inertia and torque box (the torque fraction already applied).
    target : SlewTarget
    settings : SearchSettings

    Returns
    -------
    GlobalSlew

    Raises
    ------
    SlewInfeasibleError
        No start converged.
    """
    slew = rigid_slew(body, target, settings.intervals)
    workers = settings.processes()
    started = time.perf_counter()
    search = run_starts(
        slew, make_starts(slew, settings.starts, settings.seed), settings.seed, workers
    )
    best, images, families = _images(slew, search, workers)
    search_s = time.perf_counter() - started
    report = _search_report(slew, search, families, images, best)
    report.update({"workers": workers, "multistart_time_s": search_s})
    scale = slew.time_scale_s
    controls, knots, status = (
        best.controls,
        np.linspace(0.0, best.duration, settings.intervals + 1),
        best.status,
    )
    if settings.refine:
        started = time.perf_counter()
        refined = _refined(slew, best, report)
        report["refinement_time_s"] = time.perf_counter() - started
        if refined is not None:
            controls, knots, status = refined
    else:
        report["refinement"] = "not asked"
    report["segments"] = len(knots) - 1
    return GlobalSlew(
        knots_s=knots * scale,
        torque_Nm=controls * body.torque_scale_Nm,
        status=status,
        limit_duration_s=scale,
        report=report,
    )


def _images(
    slew: RigidSlew, search: MultiStartResult, workers: int
) -> tuple[StartOutcome, tuple[StartOutcome, ...], dict[float, float]]:
    """Solve the symmetric images of the shortest ``IMAGED_OPTIMA`` distinct optima.

    Returns
    -------
    best : StartOutcome
        The best of the starts and the images.
    images : tuple of StartOutcome
        The images' outcomes.
    families : dict
        Each imaged optimum (scaled duration) and the best of it and its images.
    """
    converged = [o for o in search.outcomes if o.converged]
    representatives = [_nearest(converged, optimum) for optimum in search.optima[:IMAGED_OPTIMA]]
    per_optimum = [symmetric_images(slew, o) for o in representatives]
    starts = [image for images in per_optimum for image in images]
    solved = run_starts(slew, starts, search.seed, workers).outcomes if starts else ()
    families, position = {}, 0
    for outcome, images in zip(representatives, per_optimum, strict=True):
        found = [o.duration for o in solved[position : position + len(images)] if o.converged]
        families[outcome.duration] = min([outcome.duration, *found])
        position += len(images)
    best = min((o for o in (*converged, *solved) if o.converged), key=lambda o: o.duration)
    return best, tuple(solved), families


def _nearest(outcomes: list[StartOutcome], duration: float) -> StartOutcome:
    """The outcome whose duration is nearest ``duration``."""
    return min(outcomes, key=lambda outcome: abs(outcome.duration - duration))


def _search_report(
    slew: RigidSlew,
    search: MultiStartResult,
    families: dict[float, float],
    images: tuple[StartOutcome, ...],
    best: StartOutcome,
) -> dict[str, Any]:
    """The multi-start figures (s), and the warning when starts disagree."""
    scale, target = slew.time_scale_s, best.duration

    def near(value: float, reference: float) -> bool:
        return abs(value - reference) <= AGREEMENT_TOLERANCE * reference

    def reached(outcome: StartOutcome) -> float:
        for optimum, family_best in families.items():
            if near(outcome.duration, optimum):
                return family_best
        return outcome.duration

    converged = [o for o in search.outcomes if o.converged]
    agreeing = sum(1 for o in converged if near(reached(o), target))
    found = distinct([o.duration for o in (*converged, *images) if o.converged])
    count = len(search.outcomes)
    report = {
        "starts": count,
        "seed": search.seed,
        "starts_converged": len(converged),
        "starts_agreeing": agreeing,
        "starts_agreeing_direct": sum(1 for o in converged if near(o.duration, target)),
        "agreement_fraction": agreeing / count,
        "symmetric_images": len(images),
        "best_start": best.label,
        "collocation_duration_s": best.duration * scale,
        "local_optima_s": [value * scale for value in found],
    }
    if agreeing < count:
        others = ", ".join(f"{value * scale:.6g}" for value in found[1:]) or "none"
        logger.warning(
            "time-optimal slew: %d of %d starts reach the best, %.6g s (%d converged; "
            "other local optima: %s s): the best found may not be the global optimum",
            agreeing,
            count,
            target * scale,
            len(converged),
            others,
        )
    return report


def _refined(
    slew: RigidSlew, best: StartOutcome, report: dict[str, Any]
) -> tuple[np.ndarray, np.ndarray, str] | None:
    """The best solution's switch times refined: (scaled controls, scaled knots, status),
    or None (and why in ``report["refinement"]``) when it is not bang-bang, does not
    converge or does not verify."""
    try:
        structure = switch_structure(slew, best)
    except NotBangBangError as error:
        report["refinement"] = f"none: {error}"
        return None
    refined = refine(slew, structure)
    scale = slew.time_scale_s
    report.update(
        {
            "verification_attitude_error_rad": refined.attitude_error_rad,
            "verification_rate_rad_s": refined.rate_error / scale,
            "refined_duration_s": refined.duration * scale,
        }
    )
    if not refined.verified:
        report["refinement"] = (
            f"none: the switch times did not verify (ipopt: {refined.status}, attitude error "
            f"{refined.attitude_error_rad:.2g} rad)"
        )
        logger.warning(
            "time-optimal slew: %s; the collocation result is kept", report["refinement"]
        )
        return None
    if refined.duration > best.duration * (1.0 + AGREEMENT_TOLERANCE):
        report["refinement"] = "none: the switch times came out longer than the collocation"
        return None
    kept = refined.structure.durations > MIN_SEGMENT
    durations = refined.structure.durations[kept]
    switches = refined.structure.switch_times()
    report["refinement"] = "switch times"
    for name, times in zip("xyz", switches, strict=True):
        report[f"switch_times_{name}_s"] = [t * scale for t in times]
    controls = refined.structure.controls(slew)[kept]
    knots = np.concatenate([[0.0], np.cumsum(durations)])
    return controls, knots, refined.status


def rigid_body_profile(
    body: RigidBody,
    target: SlewTarget,
    result: GlobalSlew,
    *,
    sample_s: float,
    solve_time_s: float,
    figures: Mapping[str, object],
) -> SlewProfile:
    """The slew of a :class:`RigidBody` as a profile, integrated by CVODES on its own
    equations (a rigid body has no engines: no thrust, no fuel, no vibration).

    Parameters
    ----------
    body : RigidBody
    target : SlewTarget
    result : GlobalSlew
    sample_s : float
        Output spacing, s (the knots are added).
    solve_time_s : float
        Wall time of the solve, s.
    figures : mapping
        The search's figures (units in the keys), added to the profile's
        ``settings`` record.
    """
    knots, torque = result.knots_s, result.torque_Nm
    input_function = zoh_input_function(knots, torque)
    grid = sample_grid(result.duration_s, sample_s, knots)
    ode = scaled_rigid_ode(body, 1.0)  # SI: unit time scale, torque over its scale
    x, t = ca.SX.sym("x", N_RIGID_STATE), ca.SX.sym("t")
    u = input_function(t)[0:3] / ca.DM(body.torque_scale_Nm)
    integrator = ca.integrator(
        "rigid_body_slew",
        "cvodes",
        {"x": x, "t": t, "ode": ode(x, u)},
        0.0,
        grid,
        INTEGRATOR_OPTIONS,
    )
    start = np.concatenate([target.q_initial_BN, np.zeros(3)])
    states = np.array(integrator(x0=start)["xf"]).T
    torque_samples = np.array(input_function.map(len(grid))(grid)).T[:, 0:3]
    scaled = torque_samples / body.torque_scale_Nm
    accelerations = np.array(
        [np.array(ode(s, v)).ravel()[4:7] for s, v in zip(states, scaled, strict=True)]
    )
    final_error = attitude_error(target.q_final_BN, states[-1, 0:4])
    return SlewProfile(
        method="time-optimal",
        target=target,
        flexible=False,
        thrusters=False,
        time_s=grid,
        quaternion_BN=states[:, 0:4],
        rate_rad_s=states[:, 4:7],
        acceleration_rad_s2=accelerations,
        torque_Nm=torque_samples,
        thrust_N=np.zeros((len(grid), 0)),
        input_function=input_function,
        duration_s=result.duration_s,
        fuel_kg=math.nan,
        limit_duration_s=result.limit_duration_s,
        solve_time_s=solve_time_s,
        solver_status=result.status,
        residual_vibration_rad=0.0,
        residual_energy_J=0.0,
        limits=box_check(grid, torque_samples, body.lower_Nm, body.upper_Nm),
        eigenaxis_duration_s=_box_eigenaxis_s(body, target),
        settings={
            "final_attitude_error_rad": float(np.linalg.norm(final_error)),
            "final_rate_rad_s": float(np.linalg.norm(states[-1, 4:7])),
            **figures,
            **result.report,
        },
    )


def _box_eigenaxis_s(body: RigidBody, target: SlewTarget) -> float:
    """The eigenaxis bang-bang time within the body's torque box, gyroscopic torque
    included, s (:func:`~casadi_debris.slews._maneuver.eigenaxis_duration_s`)."""
    authority = box_authority(body.lower_Nm, body.upper_Nm)

    def use(torques_Nm: np.ndarray) -> np.ndarray:
        return axis_ratios(authority, torques_Nm).max(axis=1)

    return eigenaxis_duration_s(target.angle_rad, body.inertia_kgm2, target.axis_B, use)
