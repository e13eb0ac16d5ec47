"""What a failure campaign gives a user, as typed records (one JSON form each).

Units in the names, CubeSats and stages numbered from 1. The contract of
``summary.json``: every case has ``failed`` (failed CubeSats),
``failed_stage`` (CubeSats that lost a stage), ``torque_max_zero_force_mNm``
(``+x, -x, +y, -y, +z, -z``, as ``casadi-debris model`` names them) and
``closed_loop`` with its verdict ``met``.
"""

from __future__ import annotations

from dataclasses import dataclass

from casadi_debris.records import Record


@dataclass(frozen=True, kw_only=True)
class RunCheckSummary(Record):
    """A manoeuvre's worst run for one failure case, against its requirement.

    Attributes
    ----------
    manoeuvre : str
        ``"slew"`` or ``"pointing"``.
    error_key : str
        The run figure judged: ``"max_error_deg"`` or ``"max_error_arcsec"``.
    error : float or None
        Its value in the worst run (None: a run raised).
    required : float
        Its largest allowed value (same unit).
    met : bool or None
        ``error <= required`` (None: a run raised).
    runs : int
        Runs judged (plants).
    worst_case_id : str
        The run the figures come from, ``<failure case>@<plant>``.
    fuel_kg, fuel_worst_cubesat_kg : float or None
    fuel_per_cubesat_kg : tuple of float
    fuel_spread : float or None
        The most a surviving CubeSat burnt over their mean (1: evenly spread).
    torque_saturated_s : float or None
    settle_time_s : float or None
    stage_switches : int or None
    wall_time_s : float or None
    error_message : str or None
        What a run that raised said.
    """

    manoeuvre: str
    error_key: str
    error: float | None
    required: float
    met: bool | None
    runs: int
    worst_case_id: str
    fuel_kg: float | None = None
    fuel_worst_cubesat_kg: float | None = None
    fuel_per_cubesat_kg: tuple[float, ...] = ()
    fuel_spread: float | None = None
    torque_saturated_s: float | None = None
    settle_time_s: float | None = None
    stage_switches: int | None = None
    wall_time_s: float | None = None
    error_message: str | None = None

    @property
    def excess(self) -> float:
        """The figure over its requirement (inf when a run raised)."""
        return float("inf") if self.error is None else self.error / self.required


@dataclass(frozen=True)
class ClosedLoopCheckSummary(Record):
    """A case's closed-loop runs: ``met`` when every one is within its requirement
    (None: none flown, or one raised and none missed)."""

    met: bool | None
    nominal: dict[str, RunCheckSummary]
    corners: dict[str, RunCheckSummary]


@dataclass(frozen=True)
class HoldingSummary(Record):
    """The allocation of the torque that cancels the disturbance over one period.

    See :func:`~casadi_debris.studies.failures.case_authority` for how each figure is computed.
    """

    period_s: float
    fuel_per_period_kg: float
    fuel_per_cubesat_kg: tuple[float, ...]
    fuel_spread: float | None
    thrust_per_cubesat_mN: tuple[float, ...]
    saturated_fraction: float
    depletion_time_s: float | None
    first_depleted_cubesat: int | None


@dataclass(frozen=True)
class ThrustChange(Record):
    """A CubeSat's mean holding thrust before and after a failure [mN]."""

    cubesat: int
    thrust_before_mN: float
    thrust_after_mN: float


@dataclass(frozen=True, kw_only=True)
class FailureCaseSummary(Record):
    """One case of a failure campaign, as ``summary.json`` lists it.

    Attributes
    ----------
    case_id : str
    failed : tuple of int
        Failed CubeSats, from 1.
    failed_stage : tuple of int
        CubeSats (from 1) that lost stage ``stage``.
    stage : int or None
    label : str
    torque_max_zero_force_mNm : dict
        Largest pure torque per signed axis at zero net force [mNm].
    authority_ratio : dict
        That over the disturbance's amplitude about the axis (None: no disturbance).
    worst_axis : str
    worst_ratio : float
    authority_loss : dict or None
        Share of the whole swarm's authority lost per signed axis (None for the baseline).
    holding : HoldingSummary or None
        None when no engine is left.
    reallocation : tuple of ThrustChange
        The CubeSats whose mean holding thrust rises most, the largest rise first.
    closed_loop : ClosedLoopCheckSummary
    """

    case_id: str
    failed: tuple[int, ...]
    failed_stage: tuple[int, ...]
    stage: int | None
    label: str
    torque_max_zero_force_mNm: dict[str, float]
    authority_ratio: dict[str, float]
    worst_axis: str
    worst_ratio: float
    authority_loss: dict[str, float | None] | None
    holding: HoldingSummary | None
    reallocation: tuple[ThrustChange, ...]
    closed_loop: ClosedLoopCheckSummary


@dataclass(frozen=True)
class ManoeuvreRunSummary(Record):
    """A run every case flew."""

    name: str
    problem: str
    duration_s: float


@dataclass(frozen=True, kw_only=True)
class FailuresSummary(Record):
    """A failure campaign: what was run, the whole swarm, and every case, the worst first.

    ``controller_path``, ``quick``, ``max_corners`` and ``out_dir`` are the job's (see
    :func:`~casadi_debris.workflows._failures.failures`). ``disturbance_period_s``
    is what the pointing run's window is judged against (None in summaries written
    before it was kept).
    """

    problem: str
    problem_sha256: str
    max_failed: int
    stages: bool
    closed_loop: bool
    corner_sets: int
    workers: int
    jit: bool
    cubesats: int
    disturbance_mNm: tuple[float, ...]
    requirements: dict[str, float]
    manoeuvres: tuple[ManoeuvreRunSummary, ...]
    corner_plants: int
    case_count: int
    cases_met: int
    cases_not_met: int
    baseline: FailureCaseSummary
    cases: tuple[FailureCaseSummary, ...]
    wall_time_s: float
    controller_path: str | None = None
    quick: bool = False
    max_corners: int | None = None
    out_dir: str | None = None
    disturbance_period_s: float | None = None
