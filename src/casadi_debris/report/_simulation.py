"""Run folders of closed-loop simulations and Monte-Carlo campaigns.

A single run: ``summary.json``, ``series.csv`` (time series, units in the
column names), ``closed_loop.png`` and ``thrust.png``.

A campaign: ``summary.json`` (worst case of every figure, counts, seed, and
the statistics of :mod:`casadi_debris.campaigns`), ``cases.csv``
(one row per case, with the value of every varied quantity), ``envelope.csv``,
``statistics.png``, ``campaign.nc`` (every
case as labelled arrays, see :func:`casadi_debris.store.open_campaign`),
``nominal/`` (the nominal run), ``envelope.png``, and ``cases/<id>.json`` +
``cases/<id>.npz`` per case (written as they finish, see
:class:`casadi_debris.store.CampaignFolder`).
"""

from __future__ import annotations

import csv
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypedDict

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.campaigns import (
    CampaignSetup,
    CampaignStatistics,
    CaseResult,
    Envelope,
    campaign_dataset,
    case_figures,
)
from casadi_debris.config import AXIS_NAMES, Problem
from casadi_debris.geometry import build_geometry
from casadi_debris.plots import closed_loop_figure, save_figure, statistics_figure, thrust_figure
from casadi_debris.records import FLATTENED, Record
from casadi_debris.simulation import ClosedLoopResult
from casadi_debris.slews import euler_angles_321
from casadi_debris.store import (
    CASE_FIGURES,
    DATASET_NAME,
    CampaignIdentity,
    write_campaign_dataset,
    write_csv,
    write_json_atomic,
)
from casadi_debris.units import ARCSEC_PER_RAD, DEG_PER_RAD, MN_PER_N, MNM_PER_NM

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def torque_limits_mNm(allocator: Allocator) -> np.ndarray:
    """Largest pure torque per axis at zero net force (the smaller of + and -), shape (3,)."""
    return allocator.torque_authority().weakest_Nm * MNM_PER_NM


def series_columns(result: ClosedLoopResult) -> dict[str, np.ndarray]:
    """The run's time series with display units; step quantities padded to the last instant."""

    def held(values: np.ndarray) -> np.ndarray:
        return np.vstack([values, values[-1:]]) if len(values) else values

    columns: dict[str, np.ndarray] = {"time_s": result.time_s}
    reference = np.degrees(np.unwrap(euler_angles_321(result.reference_BN), axis=0))
    for i, name in enumerate(("roll", "pitch", "yaw")):
        columns[f"reference_{name}_deg"] = reference[:, i]
    for i, axis in enumerate(AXIS_NAMES):
        columns[f"error_{axis}_deg"] = result.error_rad[:, i] * DEG_PER_RAD
    for i, axis in enumerate(AXIS_NAMES):
        columns[f"rate_{axis}_deg_s"] = np.degrees(result.rate_rad_s[:, i])
    for name, values in (
        ("demand", result.demand_Nm),
        ("torque", result.torque_Nm),
        ("disturbance", result.disturbance_Nm),
    ):
        padded = held(values)
        for i, axis in enumerate(AXIS_NAMES):
            columns[f"{name}_{axis}_mNm"] = padded[:, i] * MNM_PER_NM
    columns["scale"] = held(result.scale[:, None])[:, 0]
    if result.noise_seed is not None:  # realistic sensors: what the controller was told, wrong by
        estimation = held(result.estimation_error_rad)
        for i, axis in enumerate(AXIS_NAMES):
            columns[f"estimation_error_{axis}_arcsec"] = estimation[:, i] * ARCSEC_PER_RAD
    thrust = held(result.thrust_N)
    for i in range(thrust.shape[1]):
        columns[f"thrust_{i + 1:02d}_mN"] = thrust[:, i] * MN_PER_N
    return columns


class ErrorAxis(TypedDict):
    """How a run's attitude error is drawn: its unit and the requirement line in it."""

    error_unit: str
    requirement: float


def run_figures_options(problem: Problem) -> ErrorAxis:
    """Error unit and requirement line: the slew error bound in degrees for a slew, the
    pointing bound in arcsec for a hold (the problem's ``[requirements]``)."""
    if problem.simulation.reference == "hold":
        return {"error_unit": "arcsec", "requirement": problem.requirements.pointing_arcsec}
    return {"error_unit": "deg", "requirement": problem.requirements.slew_error_deg}


def write_run(
    folder: Path,
    result: ClosedLoopResult,
    summary: Record,
    problem: Problem,
    *,
    with_series: bool = True,
    with_plots: bool = True,
    title: str = "",
) -> None:
    """Write one run into an (already staged) folder."""
    write_json_atomic(folder / "summary.json", summary)
    if with_series:
        write_csv(folder / "series.csv", series_columns(result))
    if with_plots:
        for name, figure in run_figures(result, problem, title).items():
            save_figure(figure, folder / f"{name}.png")


def run_figures(result: ClosedLoopResult, problem: Problem, title: str = "") -> dict[str, Figure]:
    """A run's figures by file stem: ``closed_loop`` (reference, error against the
    requirement, torque against the authority) and ``thrust`` (every engine, and the
    propellant per CubeSat)."""
    return {
        "closed_loop": closed_loop_figure(
            result, title=title or figure_title(problem), **run_figures_options(problem)
        ),
        "thrust": thrust_figure(result, engine_groups(problem), figure_title(problem)),
    }


def figure_title(problem: Problem, width: int = 90) -> str:
    """A figure's title: the problem's description up to its first full stop, on one line."""
    line = " ".join(problem.description.split()) or problem.name
    first = re.split(r"(?<!Fig)(?<!e\.g)\. ", line, maxsplit=1)[0]
    return first if len(first) <= width else first[: width - 1] + "…"


def engine_groups(problem: Problem) -> dict[str, list[tuple[int, str]]]:
    """The engines by the face their CubeSat docks on, each labelled with its CubeSat's id
    (and its own, for a CubeSat with several): the thrust figure's panels."""
    groups: dict[str, list[tuple[int, str]]] = {}
    for cubesat in build_geometry(problem).cubesats:
        panel = f"CubeSats on the {cubesat.face} face" if cubesat.face else "other CubeSats"
        several = len(cubesat.engines) > 1
        for k, engine in enumerate(cubesat.engines):
            label = f"CubeSat {cubesat.index + 1}" + (f" engine {k + 1}" if several else "")
            groups.setdefault(panel, []).append((engine, label))
    return groups


# ----------------------------------------------------------------------------- campaigns


CASE_COLUMNS = ("case_id", "kind", "index", "seed", *CASE_FIGURES)
# How envelope.csv shows each binned quantity: name, display unit, factor from SI.
ENVELOPE_COLUMNS = {
    "error_rad": ("error", "deg", DEG_PER_RAD),
    "torque_Nm": ("torque", "mNm", MNM_PER_NM),
}


def normalized_column(parameter: str) -> str:
    """The cases.csv column of a parameter's place in the uncertainty box, -1 .. 1: a
    pure number, so without the parameter's unit (``mass_kg`` -> ``normalized_mass``)."""
    for unit in ("_kg", "_rad"):
        parameter = parameter.removesuffix(unit)
    return f"normalized_{parameter}"


@dataclass(frozen=True)
class WorstValueSummary(Record):
    """The worst value of one figure over a campaign and the case it came from.

    ``value`` is None when some cases lack the figure (a pointing run has no settling
    time); ``case_id`` then names the first such case and ``cases_without`` counts them.
    """

    value: float | None
    case_id: str
    cases_without: int = 0


@dataclass(frozen=True)
class FailedCase(Record):
    """A case that raised: the campaign recorded it and went on."""

    case_id: str
    error_type: str
    message: str


@dataclass(frozen=True)
class CampaignRun(Record):
    """What a campaign ran and how: its files (paths as they end up), cases and workers.

    ``out_dir`` is None for a campaign run from Python without a folder (until saved);
    ``seed`` is None for corner cases; ``resumed_cases`` counts the cases read back
    from an interrupted run; ``compiled_step`` whether the closed-loop step ran as
    compiled C.
    """

    controller_path: str
    controller_sha256: str
    plant_sha256: str
    controller_plant_sha256: str
    out_dir: str | None
    case_kind: str
    seed: int | None
    workers: int
    scheduler: str | None
    resumed_cases: int
    compiled_step: bool
    failed_cases: list[FailedCase]


@dataclass(frozen=True)
class CampaignSummary(Record):
    """A campaign's ``summary.json``: the worst case of every figure and what was run.

    ``nominal`` holds the nominal run's figures (units in the keys, as in
    :class:`~casadi_debris.simulation.RunSummary`); ``run`` (written as keys of
    the summary itself) the campaign's files, seed and workers; ``statistics`` the pass
    rate, moments, percentiles and rank correlations of every figure (see
    :mod:`casadi_debris.campaigns`); ``details`` any further keys a caller adds.
    """

    problem: str
    problem_sha256: str
    cases: int
    worst: dict[str, WorstValueSummary]
    max_torque_mNm: list[float]
    fuel_kg_range: list[float]
    envelope_bin_s: float
    nominal: dict[str, Any]
    run: CampaignRun = field(metadata=FLATTENED)
    statistics: CampaignStatistics | None = None
    details: dict[str, Any] = field(default_factory=dict, metadata=FLATTENED)


WORST_FIGURES = (
    "max_error_deg",
    "max_error_arcsec",
    "settle_time_s",
    "fuel_kg",
    "fuel_worst_cubesat_kg",
    "torque_saturated_s",
)
"""The run figures a campaign summary gives the worst case of."""


def campaign_summary(
    problem: Problem,
    setup: CampaignSetup,
    outcomes: list[CaseResult],
    nominal: dict[str, Any],
    run: CampaignRun,
    statistics: CampaignStatistics | None = None,
) -> CampaignSummary:
    """Worst case of every figure over the campaign, and which case it was (and the
    campaign's ``statistics``, when given)."""
    runs = [o.summary.run for o in outcomes]
    case_ids = [o.case.case_id for o in outcomes]
    fuels = [run.fuel_kg for run in runs]

    def worst(key: str) -> WorstValueSummary:
        values = [getattr(run, key) for run in runs]
        if any(v is None for v in values):
            missing = [c for c, v in zip(case_ids, values, strict=True) if v is None]
            return WorstValueSummary(None, missing[0], len(missing))
        index = int(np.argmax(values))
        return WorstValueSummary(float(values[index]), case_ids[index])

    return CampaignSummary(
        problem=problem.name,
        problem_sha256=problem.sha256,
        cases=len(outcomes),
        worst={key: worst(key) for key in WORST_FIGURES},
        max_torque_mNm=np.max([run.max_torque_mNm for run in runs], axis=0).tolist(),
        fuel_kg_range=[min(fuels), max(fuels)],
        envelope_bin_s=setup.bin_s,
        nominal=nominal,
        run=run,
        statistics=statistics,
    )


def envelope_columns(envelope: Envelope) -> dict[str, np.ndarray]:
    """The envelope in display units: ``time_s``, ``error_min_deg_x``, ... ``torque_max_mNm_z``."""
    columns = {"time_s": envelope.bin_start_s}
    if envelope.bands is None:
        return columns
    for name, extremes in envelope.bands.quantities().items():
        label, unit, factor = ENVELOPE_COLUMNS[name]
        for bound in ("min", "max"):
            values = getattr(extremes, bound) * factor
            for i, axis in enumerate(AXIS_NAMES):
                columns[f"{label}_{bound}_{unit}_{axis}"] = values[:, i]
    return columns


def write_campaign(
    folder: Path,
    problem: Problem,
    setup: CampaignSetup,
    outcomes: list[CaseResult],
    nominal: ClosedLoopResult,
    nominal_summary: Record,
    summary: CampaignSummary,
    record: CampaignIdentity,
    *,
    with_plots: bool = True,
) -> Envelope:
    """Write the campaign's tables, dataset, envelope and (``with_plots``) figures into
    ``folder`` (see :func:`campaign_figures`).

    Returns
    -------
    Envelope
        Over every case of ``outcomes``.
    """
    envelope = campaign_envelope(setup, outcomes)
    write_json_atomic(folder / "summary.json", summary)
    varied = [name for name, _ in outcomes[0].case.varied] if outcomes else []
    with (folder / "cases.csv").open("w", newline="") as handle:
        writer = csv.writer(handle)
        normalized = [normalized_column(n) for n in nominal.parameters]
        writer.writerow([*CASE_COLUMNS, *normalized, *varied])
        for outcome in outcomes:
            flat = outcome.summary.to_json()
            row = [flat.get(c) for c in CASE_COLUMNS]
            values = [value for _, value in outcome.case.varied]
            writer.writerow([*row, *outcome.case.normalized.tolist(), *values])
    write_csv(folder / "envelope.csv", envelope_columns(envelope))
    write_campaign_dataset(
        folder / DATASET_NAME,
        campaign_dataset(record, setup.bin_start_s, outcomes, list(nominal.parameters)),
    )
    nominal_folder = folder / "nominal"
    nominal_folder.mkdir(exist_ok=True)
    write_run(nominal_folder, nominal, nominal_summary, problem, with_plots=with_plots)
    if with_plots:
        figures = campaign_figures(problem, outcomes, nominal, summary, envelope)
        for name, figure in figures.items():
            save_figure(figure, folder / f"{name}.png")
    return envelope


def campaign_envelope(setup: CampaignSetup, outcomes: list[CaseResult]) -> Envelope:
    """The min/max over every case of ``outcomes``, in the campaign's time bins."""
    envelope = Envelope(setup.bin_start_s)
    for outcome in outcomes:
        envelope.add(outcome.bands)
    return envelope


def campaign_figures(
    problem: Problem,
    outcomes: list[CaseResult],
    nominal: ClosedLoopResult,
    summary: CampaignSummary,
    envelope: Envelope,
) -> dict[str, Figure]:
    """A campaign's figures by file stem: ``envelope`` (the nominal run over the cases'
    min/max) and, with ``summary.statistics``, ``statistics`` (histograms against the
    requirement and the rank correlations, drawn by
    :func:`casadi_debris.plots.statistics_figure`)."""
    figures = {
        "envelope": closed_loop_figure(
            nominal, envelope=envelope, title=figure_title(problem), **run_figures_options(problem)
        )
    }
    if summary.statistics is not None:
        figures["statistics"] = statistics_figure(
            summary.statistics, case_figures(outcomes), title=figure_title(problem)
        )
    return figures
