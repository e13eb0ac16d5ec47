"""What a placement study gives a user, as typed records (one JSON form each).

Units in the names, CubeSats and candidates numbered from 1. The contract of
``summary.json`` (and of ``casadi-debris placement --json``): the chosen
layout's figures (``count``, ``torque_max_zero_force_mNm`` per signed axis
``+x, -x, +y, -y, +z, -z``, ``worst_ratio`` ...) at the top level beside
``solver``, ``chosen``, ``worst_failure``, ``input_layout`` (the problem's
own CubeSats judged alike) and ``pareto``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from casadi_debris.config import AXIS_NAMES, SIGNED_AXES
from casadi_debris.geometry import Authority
from casadi_debris.records import FLATTENED, Record
from casadi_debris.studies.placement._authority import WorstFailures
from casadi_debris.studies.placement._metrics import LayoutMetrics
from casadi_debris.studies.placement._milp import MilpSolve
from casadi_debris.studies.placement._pareto import ParetoPoint
from casadi_debris.studies.placement._study import PlacementStudy
from casadi_debris.units import MNM_PER_NM

SOLVER_BACKEND = "HiGHS (scipy.optimize.milp)"


def _mNm(values_Nm: Authority | np.ndarray) -> dict[str, float]:
    """Per signed axis, N m to mN m."""
    if isinstance(values_Nm, Authority):
        return values_Nm.to_mNm()
    return {name: float(v) * MNM_PER_NM for name, v in zip(SIGNED_AXES, values_Nm, strict=True)}


def _per_axis(values: np.ndarray) -> dict[str, float]:
    return dict(zip(AXIS_NAMES, np.asarray(values, dtype=float).tolist(), strict=True))


@dataclass(frozen=True)
class LayoutSummary(Record):
    """A layout's figures (see :class:`~casadi_debris.studies.placement.LayoutMetrics`)."""

    count: int
    torque_max_zero_force_mNm: dict[str, float]
    ratio_to_disturbance: dict[str, float]
    worst_axis: str
    worst_ratio: float
    rigid_slew_s: dict[str, float]
    slowest_slew_s: float
    dv_one_stage_m_s: dict[str, float]
    weakest_dv_one_stage_m_s: float
    added_inertia_kgm2: dict[str, float]
    mass_kg: float

    @classmethod
    def of(cls, metrics: LayoutMetrics) -> LayoutSummary:
        """The figures of ``metrics`` in display units."""
        return cls(
            count=metrics.count,
            torque_max_zero_force_mNm=_mNm(metrics.authority_Nm),
            ratio_to_disturbance={name: float(metrics.ratio[name]) for name in SIGNED_AXES},
            worst_axis=metrics.worst_axis,
            worst_ratio=float(metrics.worst_ratio),
            rigid_slew_s=_per_axis(metrics.slew_s),
            slowest_slew_s=metrics.slowest_slew_s,
            dv_one_stage_m_s={name: float(metrics.dv_one_stage_m_s[name]) for name in SIGNED_AXES},
            weakest_dv_one_stage_m_s=float(metrics.weakest_dv_m_s),
            added_inertia_kgm2=_per_axis(metrics.added_inertia_kgm2),
            mass_kg=float(metrics.mass_kg),
        )


@dataclass(frozen=True)
class WorstFailureSummary(Record):
    """The worst set of ``failures`` failed CubeSats per signed axis.

    Attributes
    ----------
    failures : int
        CubeSats failed per set.
    sets : int
        Sets evaluated.
    torque_min_zero_force_mNm : dict
        Least authority left per signed axis over the sets [mN m].
    worst_ratio : float
        The least of it over the disturbance.
    failed : dict
        Per signed axis, the CubeSats (ids from 1 in the layout) whose failure leaves it.
    """

    failures: int
    sets: int
    torque_min_zero_force_mNm: dict[str, float]
    worst_ratio: float
    failed: dict[str, list[int]]

    @classmethod
    def of(
        cls, worst: WorstFailures, ids: dict[int, int], disturbance_Nm: np.ndarray
    ) -> WorstFailureSummary:
        """``worst`` with candidates renamed by ``ids`` (candidate -> CubeSat id from 1)."""
        return cls(
            failures=worst.failures,
            sets=worst.sets,
            torque_min_zero_force_mNm=_mNm(worst.authority_Nm),
            worst_ratio=float(np.min(worst.ratio(disturbance_Nm))),
            failed={
                name: sorted(ids[c] for c in failed)
                for name, failed in zip(SIGNED_AXES, worst.worst_set, strict=True)
            },
        )


@dataclass(frozen=True)
class InputLayoutSummary(Record):
    """The problem's own CubeSats, judged like the chosen layout.

    ``among_candidates``: every one of them is a candidate (then the optimum is at
    least as good).
    """

    figures: LayoutSummary = field(metadata=FLATTENED)
    among_candidates: bool
    worst_failure: WorstFailureSummary


@dataclass(frozen=True)
class CandidateSummary(Record):
    """The candidates offered: mounts per face, how many, engine templates."""

    grid_per_face: tuple[int, ...]
    mounts: int
    candidates: int
    side_engines: tuple[int, ...]


@dataclass(frozen=True)
class PlacementLimits(Record):
    """The study's limits (None: none)."""

    max_added_inertia_kgm2: tuple[float, ...] | None
    max_slew_s: float | None
    slew_angle_deg: float


@dataclass(frozen=True)
class MilpSolveSummary(Record):
    """One HiGHS call (see :class:`~casadi_debris.studies.placement.MilpSolve`)."""

    status: int
    message: str
    time_s: float
    variables: int
    binaries: int
    rows: int
    blocks: int
    nodes: int | None
    mip_gap: float | None

    @classmethod
    def of(cls, solve: MilpSolve) -> MilpSolveSummary:
        """The fields of ``solve`` this record has (the same names, units and values)."""
        return cls(**{f.name: getattr(solve, f.name) for f in dataclasses.fields(cls)})


@dataclass(frozen=True)
class SolverSummary(Record):
    """How sure the MILP is of its layout (``optimal``: proven within ``mip_rel_gap``)."""

    backend: str
    optimal: bool
    objective: float
    upper_bound: float
    gap: float
    mip_rel_gap: float
    method: str
    blocks_extensive: int
    blocks_used: int
    time_s: float
    solves: tuple[MilpSolveSummary, ...]

    @classmethod
    def of(cls, study: PlacementStudy) -> SolverSummary:
        solution = study.solution
        return cls(
            backend=SOLVER_BACKEND,
            optimal=solution.optimal,
            objective=solution.objective,
            upper_bound=solution.upper_bound,
            gap=solution.gap,
            mip_rel_gap=study.settings.mip_rel_gap,
            method=solution.method,
            blocks_extensive=solution.blocks_total,
            blocks_used=solution.blocks_used,
            time_s=solution.time_s,
            solves=tuple(MilpSolveSummary.of(s) for s in solution.solves),
        )


@dataclass(frozen=True)
class ChosenCubeSat(Record):
    """A CubeSat of the chosen layout: its id, candidate and mount (all from 1)."""

    cubesat: int
    candidate: int
    mount: int
    face: str
    template: str
    position_corner_m: tuple[float, ...]


@dataclass(frozen=True)
class ParetoPointSummary(Record):
    """A point of the Pareto sweep (``candidates`` from 1; None: no layout found)."""

    label: str
    count: int
    worst_ratio: float
    worst_axis: str
    slowest_slew_s: float
    weakest_dv_one_stage_m_s: float
    max_slew_s: float | None
    optimal: bool
    on_front: bool
    candidates: tuple[int, ...] | None

    @classmethod
    def of(cls, point: ParetoPoint) -> ParetoPointSummary:
        metrics = point.metrics
        return cls(
            label=point.label,
            count=metrics.count,
            worst_ratio=float(metrics.worst_ratio),
            worst_axis=metrics.worst_axis,
            slowest_slew_s=metrics.slowest_slew_s,
            weakest_dv_one_stage_m_s=float(metrics.weakest_dv_m_s),
            max_slew_s=point.max_slew_s,
            optimal=point.optimal,
            on_front=point.on_front,
            candidates=None if point.chosen is None else tuple(c + 1 for c in point.chosen),
        )


@dataclass(frozen=True, kw_only=True)
class PlacementSummary(Record):
    """A placement study: what was asked, the solver, the chosen layout's figures
    (written at the top level), its worst failures, the input layout, the Pareto sweep.

    ``out_dir`` is the job's (see :func:`~casadi_debris.workflows._placement.placement`).
    """

    problem: str
    problem_sha256: str
    objective: str
    count_limits: tuple[int, ...]
    candidates: CandidateSummary
    limits: PlacementLimits
    solver: SolverSummary
    chosen: tuple[ChosenCubeSat, ...]
    figures: LayoutSummary = field(metadata=FLATTENED)
    worst_failure: WorstFailureSummary
    input_layout: InputLayoutSummary
    pareto: tuple[ParetoPointSummary, ...]
    out_dir: str | None = None


def placement_summary(
    study: PlacementStudy, objective: str, pareto: list[ParetoPoint]
) -> PlacementSummary:
    """The record of ``study`` (``objective``: the name of what it maximised)."""
    solution, settings = study.solution, study.settings
    disturbance_Nm = np.abs(study.problem.disturbance.amplitude_mNm) / MNM_PER_NM
    ids = {candidate: i + 1 for i, candidate in enumerate(solution.chosen)}
    own = study.input_layout
    candidates = study.candidates
    return PlacementSummary(
        problem=study.problem.name,
        problem_sha256=study.problem.sha256,
        objective=objective,
        count_limits=tuple(settings.count),
        candidates=CandidateSummary(
            grid_per_face=tuple(candidates.grid),
            mounts=candidates.n_mounts,
            candidates=len(candidates.candidates),
            side_engines=tuple(candidates.side_engine_options),
        ),
        limits=PlacementLimits(
            max_added_inertia_kgm2=settings.max_added_inertia_kgm2,
            max_slew_s=settings.max_slew_s,
            slew_angle_deg=settings.slew_angle_deg,
        ),
        solver=SolverSummary.of(study),
        chosen=tuple(
            ChosenCubeSat(
                cubesat=i + 1,
                candidate=c.index + 1,
                mount=c.mount + 1,
                face=c.face,
                template=c.template,
                position_corner_m=tuple(c.cubesat.position_corner_m.tolist()),
            )
            for i, c in enumerate(study.chosen)
        ),
        figures=LayoutSummary.of(study.metrics),
        worst_failure=WorstFailureSummary.of(solution.worst, ids, disturbance_Nm),
        input_layout=InputLayoutSummary(
            figures=LayoutSummary.of(own.metrics),
            among_candidates=own.among_candidates is not None,
            worst_failure=WorstFailureSummary.of(
                own.worst, {i: i + 1 for i in range(own.metrics.count)}, disturbance_Nm
            ),
        ),
        pareto=tuple(ParetoPointSummary.of(p) for p in pareto),
    )
