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
from typing import Any

import control

from casadi_debris.config import Problem
from casadi_debris.simulation import (
    CampaignSetup,
    Case,
    CaseOutcome,
    run_campaign,
    scenario_reference,
)
from casadi_debris.simulation.monte_carlo import CaseFailure
from casadi_debris.studies.failure_cases import FailureCase

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


@dataclass(frozen=True, eq=False)
class RunVerdict:
    """A manoeuvre's worst run for one failure case (one run on the nominal plant).

    Attributes
    ----------
    manoeuvre : str
    error_key : str
    error : float or None
        The judged figure of the worst run (None: a run raised).
    required : float
    runs : int
        Runs judged (plants).
    worst_case_id : str
        The run the figure comes from (``<failure case>@<plant>``).
    figures : dict
        The worst run's summary figures: fuel (total, per CubeSat, spread over the
        survivors), saturated time, settling, wall time.
    error_message : str or None
        What a run that raised said.
    """

    manoeuvre: str
    error_key: str
    error: float | None
    required: float
    runs: int
    worst_case_id: str
    figures: dict[str, Any]
    error_message: str | None = None

    @property
    def met(self) -> bool | None:
        """Within the requirement on every run; None when a run raised."""
        return None if self.error is None else self.error <= self.required

    @property
    def excess(self) -> float:
        """The figure over its requirement (inf when a run raised)."""
        return float("inf") if self.error is None else self.error / self.required

    def to_dict(self) -> dict[str, Any]:
        """For JSON, with ``met``."""
        return {
            self.error_key: self.error,
            f"required_{self.error_key.removeprefix('max_')}": self.required,
            "met": self.met,
            "runs": self.runs,
            "worst_case_id": self.worst_case_id,
            **self.figures,
            **({"error": self.error_message} if self.error_message else {}),
        }


FIGURE_KEYS = (
    "fuel_kg",
    "fuel_worst_cubesat_kg",
    "fuel_per_cubesat_kg",
    "torque_saturated_s",
    "settle_time_s",
    "stage_switches",
    "wall_time_s",
)


def run_id(case: FailureCase, plant: Case) -> str:
    """Id of the run of ``case`` on ``plant``: ``failed-3-17@nominal``."""
    return f"{case.case_id}{CASE_SEPARATOR}{plant.case_id}"


def _figures(summary: dict[str, Any], case: FailureCase) -> dict[str, Any]:
    figures = {key: summary.get(key) for key in FIGURE_KEYS}
    fuel = [f for i, f in enumerate(summary["fuel_per_cubesat_kg"]) if i not in case.cubesats]
    mean = sum(fuel) / len(fuel) if fuel else 0.0
    figures["fuel_spread"] = max(fuel) / mean if mean > 0 else None
    return figures


def verdicts(
    manoeuvre: Manoeuvre,
    cases: Sequence[FailureCase],
    outcomes: dict[str, CaseOutcome],
    failures: dict[str, CaseFailure],
    plants: Sequence[Case],
) -> dict[str, RunVerdict]:
    """Each failure case's worst run over ``plants`` (by the judged figure), by case id."""
    judged: dict[str, RunVerdict] = {}
    for case in cases:
        ids = [run_id(case, plant) for plant in plants]
        raised = [failures[i] for i in ids if i in failures]
        done = [outcomes[i] for i in ids if i in outcomes]
        if raised:
            first = raised[0]
            judged[case.case_id] = RunVerdict(
                manoeuvre=manoeuvre.name,
                error_key=manoeuvre.error_key,
                error=None,
                required=manoeuvre.required,
                runs=len(ids),
                worst_case_id=first.case.case_id,
                figures={},
                error_message=f"{first.error_type}: {first.message}",
            )
            continue
        worst = max(done, key=lambda outcome: outcome.summary[manoeuvre.error_key])
        judged[case.case_id] = RunVerdict(
            manoeuvre=manoeuvre.name,
            error_key=manoeuvre.error_key,
            error=float(worst.summary[manoeuvre.error_key]),
            required=manoeuvre.required,
            runs=len(done),
            worst_case_id=worst.case.case_id,
            figures=_figures(worst.summary, case),
        )
    return judged


def fly_cases(
    manoeuvre: Manoeuvre,
    controller: control.StateSpace,
    cases: Sequence[FailureCase],
    plants: Sequence[Case],
    *,
    workers: int = 1,
    jit: bool = False,
    progress: Progress | None = None,
) -> dict[str, RunVerdict]:
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
        Compile the step to C. Each failure set has its own authority polytope, which the
        compiled step holds as constants: one compile (seconds) per set, worth it only
        when a set flies many plants.
    progress : callable, optional
        ``progress(done, total)`` as runs finish.

    Returns
    -------
    dict
        :class:`RunVerdict` by failure case id.
    """
    setup = CampaignSetup.create(
        manoeuvre.problem, controller, scenario_reference(manoeuvre.problem), jit=jit
    )
    runs = [
        replace(plant, case_id=run_id(case, plant), failures=case.events)
        for case in cases
        for plant in plants
    ]
    outcomes: dict[str, CaseOutcome] = {}
    failures: dict[str, CaseFailure] = {}

    def finished(item: CaseOutcome | CaseFailure) -> None:
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
