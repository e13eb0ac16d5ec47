"""The failure study: every case's authority, holding load and closed-loop runs, ranked
(:func:`failure_study`); the package's docstring tells what each case gives."""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import control
import numpy as np

from casadi_debris.campaigns import DEFAULT_BATCH_CASES, Case, nominal_case
from casadi_debris.config import SIGNED_AXES, Problem
from casadi_debris.dynamics import Model
from casadi_debris.studies.failures._authority import (
    CaseAuthority,
    case_authority,
    holding_torque_Nm,
)
from casadi_debris.studies.failures._cases import (
    FAILED_STAGE,
    FailureCase,
    FailureStudyError,
    failure_cases,
)
from casadi_debris.studies.failures._records import (
    ClosedLoopCheckSummary,
    FailureCaseSummary,
    FailuresSummary,
    ManoeuvreRunSummary,
    RunCheckSummary,
    ThrustChange,
)
from casadi_debris.studies.failures._runs import Manoeuvre, StageProgress, fly_cases
from casadi_debris.units import MN_PER_N, SECONDS_PER_MINUTE

LOGGER = logging.getLogger(__name__)
REALLOCATION_SHOWN = 5
"""CubeSats a case's ``reallocation`` lists (those whose holding thrust rises most)."""
RANK_DIGITS = 9
"""Decimals of the ranked figures: closer values are ties, left in the order of the cases."""
THRUST_RISE_RTOL = 1e-6
"""A rise of the mean holding thrust below this share of the largest is round-off."""


@dataclass(frozen=True)
class FailureSettings:
    """What a failure study covers.

    Attributes
    ----------
    max_failed : int
        Largest number of CubeSats failed at once (1 .. the swarm's).
    stages : bool
        Also a lost first stage per CubeSat.
    closed_loop : bool
        Fly the manoeuvres for every case.
    corner_sets : int
        How many of the worst cases also fly the corner plants.
    workers : int
        Local processes for the closed-loop runs.
    jit : bool
        Run the closed-loop cases on the compiled step, in batches (see
        :func:`~casadi_debris.studies.failures.fly_cases`).
    batch_cases : int
        Cases of one compiled call (1: one by one; same numbers).
    """

    max_failed: int = 2
    stages: bool = True
    closed_loop: bool = True
    corner_sets: int = 3
    workers: int = 1
    jit: bool = True
    batch_cases: int = DEFAULT_BATCH_CASES


@dataclass(frozen=True, eq=False)
class FailureCaseResult:
    """Everything the study found for one case.

    Attributes
    ----------
    authority : CaseAuthority
    runs : dict of str to RunCheckSummary
        Per manoeuvre, on the nominal plant (empty without closed loop).
    corners : dict of str to RunCheckSummary
        Per manoeuvre, the worst corner plant (empty unless among the worst sets).
    """

    authority: CaseAuthority
    runs: dict[str, RunCheckSummary] = field(default_factory=dict)
    corners: dict[str, RunCheckSummary] = field(default_factory=dict)

    @property
    def case(self) -> FailureCase:
        return self.authority.case

    @property
    def met(self) -> bool | None:
        """Every run within its requirement (None: not flown, or a run raised)."""
        verdicts = [v.met for v in (*self.runs.values(), *self.corners.values())]
        if False in verdicts:
            return False
        return None if not verdicts or None in verdicts else True

    @property
    def excess(self) -> float:
        """The largest nominal-plant figure over its requirement (0 when not flown).

        Only the nominal runs rank the cases: every case flies them, while only the
        worst few fly corners.
        """
        return max((v.excess for v in self.runs.values()), default=0.0)

    def rank_key(self) -> tuple[float, float, float, int, tuple[int, ...]]:
        """Sort key, the worst first: requirement missed by most on the nominal plant, least
        authority ratio, least authority; ties (to round-off) in the order of the cases."""
        authority = self.authority
        return (
            -round(self.excess, RANK_DIGITS),
            round(authority.worst_ratio, RANK_DIGITS),
            round(min(authority.torque_Nm.values()), RANK_DIGITS + 3),
            len(self.case.cubesats),
            self.case.cubesats + self.case.stage_of,
        )

    def record(self, baseline: CaseAuthority | None = None) -> FailureCaseSummary:
        """The case for ``summary.json``: ``failed``, ``torque_max_zero_force_mNm``,
        ``closed_loop`` (its verdict in ``met``), and beside the ``baseline`` (the whole
        swarm) the authority lost per signed axis and the re-allocation."""
        case, authority = self.case, self.authority
        torque = authority.torque_Nm
        loss: dict[str, float | None] | None = None
        if baseline is not None:
            loss = {
                name: 1.0 - torque[name] / baseline.torque_Nm[name]
                if baseline.torque_Nm[name] > 0
                else None
                for name in SIGNED_AXES
            }
        return FailureCaseSummary(
            case_id=case.case_id,
            failed=tuple(i + 1 for i in case.cubesats),
            failed_stage=tuple(i + 1 for i in case.stage_of),
            stage=FAILED_STAGE + 1 if case.stage_of else None,
            label=case.label,
            torque_max_zero_force_mNm=torque.to_mNm(),
            authority_ratio=authority.ratio,
            worst_axis=authority.worst_axis,
            worst_ratio=authority.worst_ratio,
            authority_loss=loss,
            holding=None if authority.holding is None else authority.holding.record(),
            reallocation=() if baseline is None else reallocation(baseline, authority),
            closed_loop=ClosedLoopCheckSummary(self.met, dict(self.runs), dict(self.corners)),
        )


def reallocation(baseline: CaseAuthority, after: CaseAuthority) -> tuple[ThrustChange, ...]:
    """The CubeSats whose mean holding thrust rises most after the failure (ids from 1),
    at most :data:`REALLOCATION_SHOWN`, the largest rise first."""
    if baseline.holding is None or after.holding is None:
        return ()
    before = baseline.holding.thrust_per_cubesat_N
    now = after.holding.thrust_per_cubesat_N
    rise = now - before
    tolerance = THRUST_RISE_RTOL * max(float(np.max(now)), float(np.max(before)), 1e-300)
    rising = [int(i) for i in np.argsort(-rise, kind="stable") if rise[i] > tolerance]
    return tuple(
        ThrustChange(i + 1, float(before[i] * MN_PER_N), float(now[i] * MN_PER_N))
        for i in rising[:REALLOCATION_SHOWN]
    )


@dataclass(frozen=True, eq=False)
class FailureStudy:
    """A failure campaign's results.

    Attributes
    ----------
    problem : Problem
    settings : FailureSettings
    baseline : FailureCaseResult
        The whole swarm, flown like every case.
    cases : tuple of FailureCaseResult
        Ranked, the worst first.
    manoeuvres : tuple of Manoeuvre
        What was flown (empty without closed loop).
    corner_plants : int
        Corner plants each of the worst sets flew.
    wall_time_s : float
    """

    problem: Problem
    settings: FailureSettings
    baseline: FailureCaseResult
    cases: tuple[FailureCaseResult, ...]
    manoeuvres: tuple[Manoeuvre, ...]
    corner_plants: int
    wall_time_s: float

    def record(self) -> FailuresSummary:
        """The study for ``summary.json``: settings, baseline, counts, cases worst first."""
        judged = [r.met for r in self.cases]
        settings = self.settings
        return FailuresSummary(
            problem=self.problem.name,
            problem_sha256=self.problem.sha256,
            max_failed=settings.max_failed,
            stages=settings.stages,
            closed_loop=settings.closed_loop,
            corner_sets=settings.corner_sets,
            workers=settings.workers,
            jit=settings.jit,
            cubesats=len(self.problem.cubesats),
            disturbance_mNm=tuple(np.abs(self.problem.disturbance.amplitude_mNm).tolist()),
            disturbance_period_s=self.problem.disturbance.period_min * SECONDS_PER_MINUTE,
            requirements={m.error_key: m.required for m in self.manoeuvres},
            manoeuvres=tuple(
                ManoeuvreRunSummary(m.name, m.problem.name, m.problem.simulation.duration_s)
                for m in self.manoeuvres
            ),
            corner_plants=self.corner_plants,
            case_count=len(self.cases),
            cases_met=sum(m is True for m in judged),
            cases_not_met=sum(m is False for m in judged),
            baseline=self.baseline.record(),
            cases=tuple(r.record(self.baseline.authority) for r in self.cases),
            wall_time_s=self.wall_time_s,
        )


def failure_study(
    model: Model,
    settings: FailureSettings,
    *,
    controller: control.StateSpace | None = None,
    manoeuvres: Sequence[Manoeuvre] = (),
    corner_plants: Sequence[Case] = (),
    cases: Sequence[FailureCase] | None = None,
    progress: StageProgress | None = None,
) -> FailureStudy:
    """Run a failure campaign on ``model.problem``.

    Parameters
    ----------
    model : Model
        The model of the problem studied (its problem is ``model.problem``).
    settings : FailureSettings
    controller : control.StateSpace, optional
        Needed with ``settings.closed_loop``: attitude error [deg] -> torque [mNm].
    manoeuvres : sequence of Manoeuvre
        What each case flies (see
        :func:`~casadi_debris.studies.failures.manoeuvres`).
    corner_plants : sequence of Case
        The plants the worst ``settings.corner_sets`` cases also fly.
    cases : sequence of FailureCase, optional
        Study these cases only (default every case of ``settings``: see
        :func:`~casadi_debris.studies.failures.failure_cases`).
    progress : callable, optional
        ``progress(stage)`` as each stage starts; may return a run counter.

    Returns
    -------
    FailureStudy

    Raises
    ------
    FailureStudyError
        ``settings.max_failed`` outside 1 .. the number of CubeSats.
    """
    problem = model.problem
    started = time.perf_counter()
    if cases is None:
        cases = failure_cases(len(problem.cubesats), settings.max_failed, stages=settings.stages)

    def stage(name: str) -> Any:
        LOGGER.info(name)
        return None if progress is None else progress(name)

    stage(f"authority and holding load of {len(cases)} failure cases")
    holding = holding_torque_Nm(model)
    baseline = case_authority(problem, model.geometry, FailureCase(), holding)
    authorities = [case_authority(problem, model.geometry, c, holding) for c in cases]
    flown = tuple(manoeuvres) if settings.closed_loop else ()
    if flown and controller is None:
        raise FailureStudyError("closed-loop runs need a controller")
    every = [FailureCase(), *cases]
    fly = _Flights(flown, controller, settings, stage)
    runs = fly(every, [nominal_case(model)], f"nominal plant: {len(every)} cases")
    results = [FailureCaseResult(a, runs.get(a.case.case_id, {})) for a in authorities]
    ranked = sorted(results, key=FailureCaseResult.rank_key)
    worst = [r.case for r in ranked[: settings.corner_sets]] if corner_plants else []
    where = f"{len(corner_plants)} corners of the {len(worst)} worst cases"
    corners = fly(worst, corner_plants, where) if worst else {}
    results = [
        FailureCaseResult(r.authority, r.runs, corners.get(r.case.case_id, {})) for r in ranked
    ]
    return FailureStudy(
        problem=problem,
        settings=settings,
        baseline=FailureCaseResult(baseline, runs.get("none", {})),
        cases=tuple(sorted(results, key=FailureCaseResult.rank_key)),
        manoeuvres=flown,
        corner_plants=len(corner_plants) if worst else 0,
        wall_time_s=time.perf_counter() - started,
    )


@dataclass(frozen=True, eq=False)
class _Flights:
    """Every manoeuvre flown by failure cases on plants, each announced as a stage."""

    manoeuvres: tuple[Manoeuvre, ...]
    controller: control.StateSpace | None
    settings: FailureSettings
    stage: Callable[[str], Any]

    def __call__(
        self, cases: Sequence[FailureCase], plants: Sequence[Case], where: str
    ) -> dict[str, dict[str, RunCheckSummary]]:
        """``{case id: {manoeuvre: verdict}}`` of ``cases`` on ``plants``."""
        judged: dict[str, dict[str, RunCheckSummary]] = {c.case_id: {} for c in cases}
        for manoeuvre in self.manoeuvres:
            verdicts = fly_cases(
                manoeuvre,
                self.controller,
                cases,
                plants,
                workers=self.settings.workers,
                jit=self.settings.jit,
                batch_cases=self.settings.batch_cases,
                progress=self.stage(f"{manoeuvre.name}, {where}"),
            )
            for case_id, verdict in verdicts.items():
                judged[case_id][manoeuvre.name] = verdict
        return judged
