"""Closed-loop runs of a failure campaign: does the swarm still meet its requirements?

Every failure case flies each of the problem's manoeuvres (a slew, judged
against ``[requirements] slew_error_deg``, and an attitude hold, judged
against ``pointing_arcsec``) on the nominal plant, and on chosen corners of
the uncertainty set for the worst cases. Each run is one
:class:`~casadi_debris.simulation.Case` of a campaign
(:func:`~casadi_debris.simulation.run_campaign`, in parallel) carrying the
case's failures, so that ``casadi-debris simulate`` with the same failures
gives the same numbers.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import control

from casadi_debris.campaigns import (
    DEFAULT_BATCH_CASES,
    CampaignSetup,
    Case,
    CaseFailure,
    CaseResult,
    run_campaign,
)
from casadi_debris.config import Problem
from casadi_debris.guidance import scenario_reference
from casadi_debris.simulation import RunSummary
from casadi_debris.studies.failures._cases import FailureCase
from casadi_debris.studies.failures._records import RunCheckSummary

Progress = Callable[[int, int], None]
"""``progress(done, total)``: runs finished of the runs of one stage."""
StageProgress = Callable[[str], Progress | None]
"""``progress(stage)`` as each stage starts; may return a run counter."""
CASE_SEPARATOR = "@"


@dataclass(frozen=True, eq=False)
class Manoeuvre:
    """A run every case flies, and the requirement it is judged against.

    Attributes
    ----------
    name : str
        ``"slew"`` or ``"pointing"``.
    problem : Problem
        The problem whose ``[simulation]`` is the run.
    error_key : str
        The run summary's figure judged: ``"max_error_deg"`` or ``"max_error_arcsec"``.
    required : float
        Its largest allowed value, in the key's unit.
    """

    name: str
    problem: Problem
    error_key: str
    required: float


def manoeuvres(slew: Problem, pointing: Problem) -> tuple[Manoeuvre, Manoeuvre]:
    """The slew and the pointing run, judged against the slew problem's ``[requirements]``."""
    required = slew.requirements
    return (
        Manoeuvre("slew", slew, "max_error_deg", required.slew_error_deg),
        Manoeuvre("pointing", pointing, "max_error_arcsec", required.pointing_arcsec),
    )


def run_id(case: FailureCase, plant: Case) -> str:
    """Id of the run of ``case`` on ``plant``: ``failed-3-17@nominal``."""
    return f"{case.case_id}{CASE_SEPARATOR}{plant.case_id}"


def _verdict(
    manoeuvre: Manoeuvre, case: FailureCase, worst: RunSummary, runs: int, run: str
) -> RunCheckSummary:
    """The verdict of ``case``'s worst run ``worst`` (named ``run``) of ``runs``."""
    error = float(getattr(worst, manoeuvre.error_key))
    fuel = [f for i, f in enumerate(worst.fuel_per_cubesat_kg) if i not in case.cubesats]
    mean = sum(fuel) / len(fuel) if fuel else 0.0
    return RunCheckSummary(
        manoeuvre=manoeuvre.name,
        error_key=manoeuvre.error_key,
        error=error,
        required=manoeuvre.required,
        met=error <= manoeuvre.required,
        runs=runs,
        worst_case_id=run,
        fuel_kg=worst.fuel_kg,
        fuel_worst_cubesat_kg=worst.fuel_worst_cubesat_kg,
        fuel_per_cubesat_kg=worst.fuel_per_cubesat_kg,
        fuel_spread=max(fuel) / mean if mean > 0 else None,
        torque_saturated_s=worst.torque_saturated_s,
        settle_time_s=worst.settle_time_s,
        stage_switches=worst.stage_switches,
        wall_time_s=worst.wall_time_s,
    )


def verdicts(
    manoeuvre: Manoeuvre,
    cases: Sequence[FailureCase],
    outcomes: dict[str, CaseResult],
    failures: dict[str, CaseFailure],
    plants: Sequence[Case],
) -> dict[str, RunCheckSummary]:
    """Each failure case's worst run over ``plants`` (by the judged figure), by case id."""
    judged: dict[str, RunCheckSummary] = {}
    for case in cases:
        ids = [run_id(case, plant) for plant in plants]
        raised = [failures[i] for i in ids if i in failures]
        done = [outcomes[i] for i in ids if i in outcomes]
        if raised:
            first = raised[0]
            judged[case.case_id] = RunCheckSummary(
                manoeuvre=manoeuvre.name,
                error_key=manoeuvre.error_key,
                error=None,
                required=manoeuvre.required,
                met=None,
                runs=len(ids),
                worst_case_id=first.case.case_id,
                error_message=f"{first.error_type}: {first.message}",
            )
            continue
        worst = max(done, key=lambda outcome: getattr(outcome.summary.run, manoeuvre.error_key))
        judged[case.case_id] = _verdict(
            manoeuvre, case, worst.summary.run, len(done), worst.case.case_id
        )
    return judged


def fly_cases(
    manoeuvre: Manoeuvre,
    controller: control.StateSpace,
    cases: Sequence[FailureCase],
    plants: Sequence[Case],
    *,
    workers: int = 1,
    jit: bool = True,
    batch_cases: int = DEFAULT_BATCH_CASES,
    progress: Progress | None = None,
) -> dict[str, RunCheckSummary]:
    """Fly ``manoeuvre`` for every failure case on every plant; the worst run of each case.

    Parameters
    ----------
    manoeuvre : Manoeuvre
    controller : control.StateSpace
        Continuous controller, attitude error [deg] -> torque [mNm].
    cases : sequence of FailureCase
    plants : sequence of Case
        The nominal case, or corners of the uncertainty set.
    workers : int
        Local processes.
    jit : bool
        Run the cases on the compiled step (compiled once per machine: the authority of
        each failure set is one of its inputs), ``batch_cases`` of them per call as one
        function mapped over them. Without it they run one by one on CasADi's virtual
        machine; the numbers are the same.
    batch_cases : int
    progress : callable, optional
        ``progress(done, total)`` as runs finish.

    Returns
    -------
    dict
        :class:`RunCheckSummary` by failure case id.
    """
    setup = CampaignSetup.create(
        manoeuvre.problem,
        controller,
        scenario_reference(manoeuvre.problem),
        jit=jit,
        batch_cases=batch_cases,
    )
    runs = [
        replace(plant, case_id=run_id(case, plant), failures=case.events)
        for case in cases
        for plant in plants
    ]
    outcomes: dict[str, CaseResult] = {}
    failures: dict[str, CaseFailure] = {}

    def finished(item: CaseResult | CaseFailure) -> None:
        if isinstance(item, CaseFailure):
            failures[item.case.case_id] = item
        else:
            outcomes[item.case.case_id] = item
        if progress is not None:
            progress(len(outcomes) + len(failures), len(runs))

    if progress is not None:
        progress(0, len(runs))
    run_campaign(setup, runs, workers=workers, on_result=finished, on_failure=finished)
    return verdicts(manoeuvre, cases, outcomes, failures, plants)
