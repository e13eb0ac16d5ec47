"""Which failures a swarm survives: every set of up to k failed CubeSats, and a lost stage.

For each case (:func:`failure_cases`: every set of failed CubeSats, a lost stage
per CubeSat) the study gives

- the torque authority left per signed axis at zero net force and its ratio to
  the disturbance, and the holding load's fuel, spread and time to first
  depletion (:func:`case_authority`);
- whether the problem's manoeuvres still meet its ``[requirements]`` in closed
  loop on the nominal plant, and for the worst sets on corners of the
  uncertainty set (:func:`fly_cases`);
- the re-allocation the failure needs: the CubeSats whose mean holding thrust
  rises, before and after.

The cases come back ranked, the worst first: those that miss a requirement (by
how far), then by the least authority relative to the disturbance.

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.dynamics import build_model
>>> from casadi_debris.studies.failures import FailureSettings, failure_study
>>> problem = load_problem()
>>> study = failure_study(build_model(problem), FailureSettings(max_failed=1,
...                       closed_loop=False))  # doctest: +SKIP
>>> len(study.cases)  # doctest: +SKIP
48
"""

from casadi_debris.studies.failures._authority import (
    HOLDING_SAMPLES,
    CaseAuthority,
    HoldingLoad,
    case_authority,
    holding_torque_Nm,
)
from casadi_debris.studies.failures._cases import (
    FAILED_STAGE,
    FailureCase,
    FailureStudyError,
    case_count,
    check_max_failed,
    failure_cases,
)
from casadi_debris.studies.failures._records import (
    ClosedLoopCheckSummary,
    FailureCaseSummary,
    FailuresSummary,
    HoldingSummary,
    ManoeuvreRunSummary,
    RunCheckSummary,
    ThrustChange,
)
from casadi_debris.studies.failures._runs import (
    Manoeuvre,
    Progress,
    StageProgress,
    fly_cases,
    manoeuvres,
    run_id,
    verdicts,
)
from casadi_debris.studies.failures._sets import (
    SetAuthority,
    authority_ratio,
    authority_without,
    axis_ratios,
    failure_sets,
    first_least,
    set_authority,
    weakest_axis,
)
from casadi_debris.studies.failures._study import (
    FailureCaseResult,
    FailureSettings,
    FailureStudy,
    failure_study,
    reallocation,
)

__all__ = [
    "FAILED_STAGE",
    "HOLDING_SAMPLES",
    "CaseAuthority",
    "ClosedLoopCheckSummary",
    "FailureCase",
    "FailureCaseResult",
    "FailureCaseSummary",
    "FailureSettings",
    "FailureStudy",
    "FailureStudyError",
    "FailuresSummary",
    "HoldingLoad",
    "HoldingSummary",
    "Manoeuvre",
    "ManoeuvreRunSummary",
    "Progress",
    "RunCheckSummary",
    "SetAuthority",
    "StageProgress",
    "ThrustChange",
    "authority_ratio",
    "authority_without",
    "axis_ratios",
    "case_authority",
    "case_count",
    "check_max_failed",
    "failure_cases",
    "failure_sets",
    "failure_study",
    "first_least",
    "fly_cases",
    "holding_torque_Nm",
    "manoeuvres",
    "reallocation",
    "run_id",
    "set_authority",
    "verdicts",
    "weakest_axis",
]
