"""The paper's method on the user's problem: design, verify, fly, with a report against
the problem's ``[requirements]``.

Scalings from the problem (:mod:`casadi_debris.robust.requirements`), D-K
mu-synthesis and reduction with a search of the performance level when the
requirement cannot be guaranteed (:mod:`casadi_debris.robust.synthesis`),
margins over sampled plants, and the slew and pointing corner campaigns. ``report.md`` puts each
figure beside the requirement it is judged against.

Example
-------
>>> import casadi_debris as cd
>>> designed = cd.design("one_array", out="runs/design-one_array", quick=True)  # doctest: +SKIP
>>> designed.summary.requirements_met, designed.summary.binding  # doctest: +SKIP
"""

from __future__ import annotations

import logging
import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import AXIS_NAMES, Problem, Simulation, slew_about, with_duration
from casadi_debris.geometry import build_geometry
from casadi_debris.report import (
    CampaignSummary,
    DesignFigures,
    DesignSummary,
    MarginsSummary,
    RequirementRow,
    VerificationSummary,
    classical_markdown,
    design_markdown,
    requirement_rows,
    torque_limits_mNm,
    verification_rows,
)
from casadi_debris.robust.plant import Controller
from casadi_debris.robust.requirements import (
    BindingLimit,
    BodyLimits,
    BodyWeights,
    WeightsChoice,
    authority_per_axis_mNm,
    body_weights,
    derived_scalings,
    hold_bandwidth_rad_s,
    margins_limit,
    mu_limit,
    pointing_limit,
    slew_limit,
)
from casadi_debris.robust.synthesis import (
    REFINEMENTS,
    ClassicalMethod,
    DesignSearch,
    SynthesisSettings,
    classical_record,
    search_design,
)
from casadi_debris.slews import rigid_limit_duration
from casadi_debris.store import RunFolder, default_run_folder, write_json_atomic
from casadi_debris.units import NM_PER_MNM, SECONDS_PER_MINUTE
from casadi_debris.workflows._campaign import Progress
from casadi_debris.workflows._controller import load_controller
from casadi_debris.workflows._reproduce import (
    FULL,
    QUICK,
    Plan,
    corner_campaigns,
    report_margins,
    stage_announcer,
)
from casadi_debris.workflows._result import ProblemLike, ReportFolderResult, as_problem

if TYPE_CHECKING:
    pass

LOGGER = logging.getLogger(__name__)
DesignMethod = Literal["mu", "pd", "pid", "lqr"]
DESIGN_METHODS: tuple[DesignMethod, ...] = ("mu", "pd", "pid", "lqr")
MEASUREMENT_NOISE_ARCSEC = 5.0
"""The star tracker's noise the LQG's Kalman filter assumes (1 sigma, a CubeSat-class
tracker's cross-boresight accuracy)."""

StageProgress = Callable[[str], Progress | None]
"""``progress(line)`` as each stage starts; may return a case counter for a campaign."""

SLEW_ANGLE_DEG = 180.0
SLEW_TORQUE_SHARE = 2.0 / 3.0
"""The verification slew's bang-bang uses this share of what the disturbance leaves of
the authority, the rest being the feedback's: ``(2/3)(1 - A_i / tau_i)``, 0.56 about the
paper's z (its 1228 s slew: 0.561)."""
QUICK_REFINEMENTS = 1
"""Bisections of the performance search in a quick run (Ve within a factor 1.41)."""
SLEW_RUN_FACTOR = 1.25
"""Run length over the slew's, for the settling (the paper: 1500 s for 1228 s)."""


def verification_problems(problem: Problem, plan: Plan = FULL) -> tuple[Problem, Problem]:
    """The slew and the pointing run a design is verified on.

    The slew is the problem's own ``[simulation.slew]`` when it has one, else
    180 deg about the slowest axis by a bang-bang at the torque fraction of
    :data:`SLEW_TORQUE_SHARE`. The pointing run
    holds the attitude for one disturbance period (shortened by a quick plan).
    Scheduled failures are left out: the design is verified on the whole swarm.
    """
    simulation = replace(problem.simulation, failures=())
    if simulation.reference == "slew":
        slew_problem = replace(problem, simulation=simulation)
    else:
        slew_problem = _default_slew(problem, simulation)
    hold = replace(simulation, reference="hold", slew=None)
    period_s = SECONDS_PER_MINUTE * problem.disturbance.period_min
    pointing_problem = with_duration(
        replace(problem, simulation=hold),
        plan.pointing_duration_s or period_s,
        "verification pointing run",
    )
    return slew_problem, pointing_problem


def _default_slew(problem: Problem, simulation: Simulation) -> Problem:
    """``problem`` flying 180 deg about its slowest axis (see :func:`verification_problems`)."""
    geometry = build_geometry(problem)
    authority_Nm = authority_per_axis_mNm(geometry) * NM_PER_MNM
    disturbance_Nm = np.abs(problem.disturbance.amplitude_mNm) * NM_PER_MNM
    fraction = SLEW_TORQUE_SHARE * (1.0 - disturbance_Nm / authority_Nm)
    acceleration = fraction * authority_Nm / np.diag(geometry.inertia_total_kgm2)
    axis = int(np.argmin(acceleration))
    slew = slew_about(
        AXIS_NAMES[axis],
        SLEW_ANGLE_DEG,
        method="bang-bang",
        start_s=0.0,
        torque_fraction=float(fraction[axis]),
    )
    slew_s = rigid_limit_duration(math.radians(SLEW_ANGLE_DEG), float(acceleration[axis]))
    return with_duration(
        replace(problem, simulation=replace(simulation, reference="slew", slew=slew)),
        math.ceil(SLEW_RUN_FACTOR * slew_s),
        "verification slew",
    )


@dataclass(frozen=True)
class DesignResult(ReportFolderResult):
    """A controller designed for a problem and verified, in the folder it was written to.

    A design writes as it goes (its campaigns keep every case on disk), so the folder is
    written when :func:`design` returns; ``save`` copies it elsewhere.

    Attributes
    ----------
    problem : Problem
    folder : Path
        The report folder written: ``controller.json``, ``report.md``, ``summary.json``,
        ``margins/``, ``slew/`` and ``pointing/``.
    record : Controller
        The controller (fly it with ``cd.simulate(..., controller=folder /
        "controller.json")``).
    margins : MarginsResult
        The margin study over sampled plants.
    summary : DesignSummary
        What ``casadi-debris design --json`` prints and ``summary.json`` holds.
    """

    problem: Problem
    record: Controller
    summary: DesignSummary

    command = "design"


def design(
    problem: ProblemLike = None,
    *,
    out: str | Path | None = None,
    quick: bool = False,
    method: DesignMethod = "mu",
    weights: WeightsChoice = "auto",
    samples: int | None = None,
    seed: int | None = None,
    workers: int | None = None,
    overwrite: bool = False,
    progress: StageProgress | None = None,
) -> DesignResult:
    """Design a controller for a problem and verify it against its ``[requirements]``.

    Weights from the body's authority, disturbance and pointing requirement, D-K
    μ-synthesis (searching the best guaranteed pointing when the requirement cannot be
    met), reduction, margins over sampled plants, and the slew and pointing corner
    campaigns; ``report.md`` puts each figure beside its requirement. The folder is
    written as the design runs (whole or not at all).

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper.
    out : str or Path, optional
        Report folder; default ``runs/design-<problem>``.
    quick : bool
        Fewer sampled plants and corners, a shorter pointing run and a coarser search
        of the performance level.
    method : {"mu", "pd", "pid", "lqr"}
        D-K μ-synthesis with the paper's weights (the default), or a per-axis PD, PID or
        LQG controller on the rigid body (:mod:`casadi_debris.robust.synthesis`) to
        compare with it; every method gets the same margins, corners and table.
    weights : {"auto", "derived", "problem"}
        Where the bandwidth and roll-off come from: ``"auto"`` derives them from the body
        unless the problem is the paper's body or sets its own
        (:mod:`~casadi_debris.robust.requirements`); ``"problem"`` takes ``[weights]`` as
        they are.
    samples, seed : int, optional
        Models for the uncertainty-weight fit and their seed; default the problem's.
    workers : int, optional
        Local processes for the campaigns; default one per core.
    overwrite : bool
        Replace a report folder this toolkit wrote.
    progress : callable, optional
        ``progress(stage)`` as each stage starts; may return a case counter for a
        campaign (:data:`~casadi_debris.workflows._campaign.Progress`).

    Returns
    -------
    DesignResult
        ``summary.rows`` (each requirement with ``met``), ``summary.requirements_met``,
        ``summary.binding`` (the limit behind each one missed), the controller, the margins.
    """
    started = time.perf_counter()
    problem = as_problem(problem)
    plan = QUICK if quick else FULL
    out = Path(out) if out is not None else default_run_folder("design", problem.name)
    workers = workers or os.cpu_count() or 1
    settings = SynthesisSettings(samples=samples, seed=seed)
    stage = stage_announcer(progress)
    derived_scalings(problem)  # refuses a problem no controller can be designed for, first
    slew_problem, pointing_problem = verification_problems(problem, plan)
    with RunFolder.claim(out, overwrite=overwrite, command="design") as staging:
        designed, search = _designed(problem, method, settings, stage, (quick, weights))
        controller_path = write_json_atomic(staging / "controller.json", designed.to_dict())
        record, controller_path = load_controller(controller_path)
        folders = (staging, out)
        margins = report_margins(problem, controller_path, plan, folders, stage)
        runs = (slew_problem, pointing_problem)
        campaigns = corner_campaigns(plan, runs, controller_path, folders, workers, stage)
        verified = _Verified(record, search, margins.summary, campaigns, slew_problem)
        how = _How(quick, workers, str(out / "controller.json"))
        summary, text = _verdict(problem, method, verified, staging, (out, started, how, weights))
        (staging / "report.md").write_text(text)
        write_json_atomic(staging / "summary.json", summary)
    return DesignResult(
        problem=problem, folder=out, record=record, margins=margins, summary=summary
    )


@dataclass(frozen=True, eq=False)
class _Verified:
    """A controller and what verified it."""

    record: Controller
    search: DesignSearch | None
    margins: MarginsSummary
    campaigns: dict[str, CampaignSummary]
    slew_problem: Problem


def _verdict(
    problem: Problem,
    method: str,
    verified: _Verified,
    staging: Path,
    run: tuple[Path, float, _How, WeightsChoice],
) -> tuple[DesignSummary, str]:
    """The summary and the report of a verified controller; warns when it misses a
    requirement (``run``: the folder, the start time, how it ran, where its weights came
    from)."""
    out, started, how, weights = run
    search, campaigns = verified.search, verified.campaigns
    limits = torque_limits_mNm(Allocator.from_problem(problem, build_geometry(problem)))
    body = body_weights(problem, weights) if search is None else search.body
    figures = DesignFigures.present_in(staging)
    if search is not None:
        rows = requirement_rows(problem, search, verified.margins, campaigns, limits)
    else:
        orders = [verified.record.reduced.nstates] * 2
        rows = verification_rows(problem, verified.margins, campaigns, limits, orders)
    binding = binding_limits(problem, rows, campaigns, search, verified.slew_problem)
    if False in (row.met for row in rows if row.key in ("margins_sampled", "unstable_samples")):
        sampled = verified.margins.sampled_min
        binding += (
            margins_limit(
                sampled.gain_margin_db,
                sampled.phase_margin_deg,
                verified.margins.unstable_samples,
                verified.margins.samples,
                None if body is None else body.bandwidth_rad_s,
            ),
        )
    how = replace(how, body=body, binding=binding)
    summary = _summary(problem, search, method, rows, campaigns, out, started, how)
    if search is not None:
        text = design_markdown(problem, search, rows, summary, figures)
    else:
        text = classical_markdown(problem, verified.record.details, rows, summary, figures)
    if not summary.requirements_met:
        LOGGER.warning(
            "%s of %s requirements met: the controller written is the best found (%s)",
            summary.requirements_passed,
            summary.requirements,
            "; ".join(f"{b.requirement}: {b.limit}" for b in summary.binding) or "see report.md",
        )
    return summary, text


def _designed(
    problem: Problem,
    method: DesignMethod,
    settings: SynthesisSettings | None,
    stage: Callable[[str], Any],
    how: tuple[bool, WeightsChoice],
) -> tuple[Controller, DesignSearch | None]:
    """The controller ``method`` designs, and the μ design's search (None for the others);
    ``how`` is (quick, where the weights come from)."""
    quick, weights = how
    if method == "mu":
        stage("designing the controller (D-K iteration)")
        refinements = QUICK_REFINEMENTS if quick else REFINEMENTS
        search = search_design(problem, settings, stage, refinements=refinements, weights=weights)
        return _record(search), search
    stage(f"designing the {method.upper()} controller on the rigid body")
    return _classical(problem, method, weights), None


def _record(search: DesignSearch) -> Any:
    """The chosen design's controller record, with the scalings and the search in its details."""
    record = search.design.record
    details = {
        **record.details,
        **({} if search.body is None else {"body_weights": search.body.figures.to_json()}),
        "derived_scalings": search.scalings.figures().to_json(),
        "performance_search": [a.to_json() for a in search.attempts],
    }
    return replace(record, details=details)


def _classical(
    problem: Problem, method: ClassicalMethod, weights: WeightsChoice = "auto"
) -> Controller:
    """A PD or LQG controller on the rigid body: bandwidth as the μ design's
    (:func:`~casadi_debris.robust.requirements.body_weights`);
    Bryson's weights from the slew requirement and the authority; the disturbance as
    process noise and :data:`MEASUREMENT_NOISE_ARCSEC` on the star tracker."""
    geometry = build_geometry(problem)
    return classical_record(
        method,
        geometry.inertia_total_kgm2,
        bandwidth_rad_s=body_weights(problem, weights, geometry).bandwidth_rad_s,
        angle_max_rad=np.full(3, math.radians(problem.requirements.slew_error_deg)),
        torque_max_Nm=authority_per_axis_mNm(geometry) * NM_PER_MNM,
        disturbance_Nm=np.abs(problem.disturbance.amplitude_mNm) * NM_PER_MNM,
        measurement_noise_rad=math.radians(MEASUREMENT_NOISE_ARCSEC / 3600.0),
        plant_sha256=problem.plant_sha256,
    )


@dataclass(frozen=True)
class _How:
    """How a design ran, as its summary records it (the controller as it will end up),
    with the body figures of its weights and the limits that bind."""

    quick: bool
    workers: int
    controller_path: str
    body: BodyWeights | None = None
    binding: tuple[BindingLimit, ...] = ()


def binding_limits(
    problem: Problem,
    rows: list[RequirementRow],
    campaigns: dict[str, CampaignSummary],
    search: DesignSearch | None,
    slew_problem: Problem,
) -> tuple[BindingLimit, ...]:
    """The limit that binds for each requirement missed.

    See :mod:`casadi_debris.robust.requirements`.
    """
    met = {row.key: row.met for row in rows}
    found: list[BindingLimit] = []
    if search is not None and not any(a.guarantees for a in search.attempts):
        lowest = min(search.attempts, key=lambda a: a.mu_peak_reduced)
        loosest = max(a.ve_ratio for a in search.attempts)
        found.append(mu_limit(lowest.mu_peak_reduced, lowest.ve_ratio, loosest))
    body = _body_limits(problem)
    required = problem.requirements
    worst_pointing = _worst(campaigns["pointing"], "max_error_arcsec")
    if met.get("pointing_arcsec") is False and worst_pointing is not None:
        found.append(pointing_limit(body, worst_pointing, required.pointing_arcsec))
    elif met.get("guaranteed_pointing_arcsec") is False and search is not None:
        guaranteed = search.chosen.guaranteed_pointing_arcsec
        if guaranteed is not None:
            bound = max(guaranteed)
            found.append(pointing_limit(body, bound, required.pointing_arcsec, guaranteed=True))
    slew = campaigns["slew"]
    worst_slew = _worst(slew, "max_error_deg")
    if met.get("slew_max_error_deg") is False and worst_slew is not None:
        reference = slew_problem.simulation.slew
        fraction = None if reference is None else reference.torque_fraction
        saturated = (
            slew.worst["torque_saturated_s"].value if "torque_saturated_s" in slew.worst else None
        )
        found.append(slew_limit(worst_slew, required.slew_error_deg, fraction, saturated))
    return tuple(found)


def _worst(campaign: CampaignSummary, key: str) -> float | None:
    """The larger of a campaign's nominal figure and its worst corner's (None: no run gave it)."""
    worst = campaign.worst.get(key)
    candidates = (campaign.nominal.get(key), None if worst is None else worst.value)
    values = [float(v) for v in candidates if v is not None]
    return max(values) if values else None


def _body_limits(problem: Problem) -> BodyLimits:
    """The body's inertia, authority, disturbance and hold bandwidth per axis, SI."""
    geometry = build_geometry(problem)
    inertia = np.diag(geometry.inertia_total_kgm2)
    authority = authority_per_axis_mNm(geometry) * NM_PER_MNM
    disturbance = np.abs(np.asarray(problem.disturbance.amplitude_mNm, dtype=float)) * NM_PER_MNM
    error = math.radians(problem.requirements.slew_error_deg)
    return BodyLimits(
        inertia_kgm2=inertia,
        authority_Nm=authority,
        disturbance_Nm=disturbance,
        hold_bandwidth_rad_s=hold_bandwidth_rad_s(inertia, authority, disturbance, error),
        disturbance_frequency_rad_s=2.0
        * math.pi
        / (SECONDS_PER_MINUTE * problem.disturbance.period_min),
    )


def _summary(
    problem: Problem,
    search: DesignSearch | None,
    method: str,
    rows: list[RequirementRow],
    campaigns: dict[str, CampaignSummary],
    out: Path,
    started: float,
    how: _How,
) -> DesignSummary:
    """What ``summary.json`` holds."""
    judged = [row for row in rows if row.met is not None]
    figures = {
        name: VerificationSummary(c.cases, c.worst, c.nominal) for name, c in campaigns.items()
    }
    chosen = None if search is None else search.chosen
    guaranteed = None if chosen is None else chosen.guaranteed_pointing_arcsec
    return DesignSummary(
        problem=problem.name,
        problem_sha256=problem.sha256,
        plant_sha256=problem.plant_sha256,
        requirements_met=all(row.met is True for row in judged),
        requirements_passed=sum(row.met is True for row in judged),
        requirements=len(judged),
        method=method,
        mu_peak=None if chosen is None else chosen.mu_peak,
        mu_peak_reduced=None if chosen is None else chosen.mu_peak_reduced,
        guaranteed_pointing_arcsec=None if guaranteed is None else list(guaranteed),
        required_pointing_arcsec=problem.requirements.pointing_arcsec,
        scalings=(derived_scalings(problem) if search is None else search.scalings).figures(),
        attempts=() if search is None else tuple(search.attempts),
        seed=None if search is None else search.design.samples.seed,
        slew=figures["slew"],
        pointing=figures["pointing"],
        rows=tuple(row.entry() for row in rows),
        time_s=time.perf_counter() - started,
        out_dir=str(out.absolute()),
        quick=how.quick,
        workers=how.workers,
        controller_path=how.controller_path,
        binding=how.binding,
        body=None if how.body is None else how.body.figures,
    )
