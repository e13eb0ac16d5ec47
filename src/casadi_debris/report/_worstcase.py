"""Worst cases as a run folder (``casadi-debris worstcase``): the mu bounds, the search,
parameter files ``simulate --parameters`` runs, and the worst run over a corner envelope.

Files: ``summary.json``; ``worst_parameters.json`` (the search's worst case),
``mu_performance_parameters.json`` and ``mu_stability_parameters.json`` (the
lower bounds' perturbations clipped to the box); ``evaluations.csv`` (every
simulation of the search); ``worstcase.png`` (the worst run, over the corner
campaign's envelope when one is given).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from casadi_debris.campaigns import Bands, Envelope, Extremes, WorstCaseSearch
from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, ParameterLayout, Parameters
from casadi_debris.plots import closed_loop_figure, save_figure
from casadi_debris.records import FLATTENED, OPTIONAL, Record
from casadi_debris.report._simulation import run_figures_options
from casadi_debris.robust.mu import (
    KINDS,
    ParametricMu,
    ParametricMuSummary,
    WorstPerturbation,
)
from casadi_debris.robust.plant import parameters_from_normalized
from casadi_debris.store import write_csv, write_json_atomic

if TYPE_CHECKING:
    from matplotlib.figure import Figure

# Campaign cases this close to the worst count as tied with it.
TIE = 1e-9


@dataclass(frozen=True)
class ParameterFile(Record):
    """A parameters file ``simulate --parameters`` runs: ``parameters`` by name (SI) and
    their box positions ``normalized`` (-1 .. 1), by name since the model's parameters
    differ from one debris to another.

    The mu files add the lower bound's perturbation (``clipped``,
    ``normalized_unclipped``, ``mu_lower``, ``omega_rad_s`` [rad/s]); the search's
    file its ``max_error_deg`` [deg]. Those absent are left out of the file.
    """

    case_id: str
    parameters: dict[str, float]
    normalized: dict[str, float]
    clipped: bool | None = field(default=None, metadata=OPTIONAL)
    normalized_unclipped: dict[str, float] | None = field(default=None, metadata=OPTIONAL)
    mu_lower: float | None = field(default=None, metadata=OPTIONAL)
    omega_rad_s: float | None = field(default=None, metadata=OPTIONAL)
    max_error_deg: float | None = field(default=None, metadata=OPTIONAL)


@dataclass(frozen=True)
class CampaignWorst(Record):
    """The corner campaign a search is compared with: its ``folder``, its number of
    ``cases``, its largest error [deg] and the case(s) that reach it."""

    folder: str
    cases: int
    worst_max_error_deg: float
    worst_cases: tuple[str, ...]


@dataclass(frozen=True)
class SearchSummary(Record):
    """The worst slew found (:class:`~casadi_debris.campaigns.WorstCaseSearch`).

    ``evaluation`` is the worst run's index among the ``simulations``; ``normalized``
    and ``parameters`` its box positions and values (SI) by name;
    ``screen_worst_corners`` the five corners the screening ranked worst; ``time_s``
    the search's wall time [s]; ``local_search`` says the answer is a local optimum.
    ``minus_campaign_worst_deg`` (with a campaign only): how far above the campaign's
    worst the search went [deg].
    """

    max_error_deg: float
    source: str
    evaluation: int
    normalized: dict[str, float]
    parameters: dict[str, float]
    simulations: int
    screen_worst_corners: tuple[int, ...]
    seed: int
    final_step: float
    time_s: float
    local_search: bool = True
    minus_campaign_worst_deg: float | None = field(default=None, metadata=OPTIONAL)


@dataclass(frozen=True)
class WorstCaseIdentity(Record):
    """What names a worst-case run: the problem, the controller and their plants, the folder
    (None until it is written)."""

    problem: str
    problem_sha256: str
    plant_sha256: str
    controller_path: str
    controller_plant_sha256: str
    out_dir: str | None


@dataclass(frozen=True)
class WorstCaseSummary(Record):
    """``casadi-debris worstcase``'s ``summary.json``: the identity, then the stages that
    ran (a skipped stage, or no ``--campaign``, leaves its key out)."""

    identity: WorstCaseIdentity = field(metadata=FLATTENED)
    mu: ParametricMuSummary | None = field(default=None, metadata=OPTIONAL)
    campaign: CampaignWorst | None = field(default=None, metadata=OPTIONAL)
    search: SearchSummary | None = field(default=None, metadata=OPTIONAL)


def parameter_file(
    layout: ParameterLayout,
    normalized: np.ndarray,
    values: np.ndarray,
    case_id: str,
    *,
    perturbation: WorstPerturbation | None = None,
    max_error_deg: float | None = None,
) -> ParameterFile:
    """The parameters file of ``values`` (SI) at box positions ``normalized``, with the mu
    lower bound's ``perturbation`` or the search's ``max_error_deg`` [deg] when given."""
    return ParameterFile(
        case_id=case_id,
        parameters=Parameters.from_vector(layout, values).to_dict(),
        normalized=_named(layout, normalized),
        clipped=None if perturbation is None else perturbation.clipped,
        normalized_unclipped=None
        if perturbation is None
        else _named(layout, perturbation.normalized_unclipped),
        mu_lower=None if perturbation is None else perturbation.mu_lower,
        omega_rad_s=None if perturbation is None else perturbation.omega_rad_s,
        max_error_deg=max_error_deg,
    )


def _named(layout: ParameterLayout, normalized: np.ndarray) -> dict[str, float]:
    return dict(zip(layout.names, np.asarray(normalized).tolist(), strict=True))


def corner_campaign_envelope(folder: Path) -> tuple[Envelope, CampaignWorst]:
    """A finished corner campaign's envelope and its worst case(s)."""
    from casadi_debris.store import open_campaign

    with open_campaign(folder) as dataset:
        error = dataset.error_rad.values
        torque = dataset.torque_Nm.values
        worst = dataset.max_error_deg.values
        cases = dataset.case.values.tolist()
        time_s = dataset.time.values
    bands = Bands(
        error_rad=Extremes(error[:, :, 0].min(axis=0), error[:, :, 1].max(axis=0)),
        torque_Nm=Extremes(torque[:, :, 0].min(axis=0), torque[:, :, 1].max(axis=0)),
    )
    top = float(np.max(worst))
    tied = tuple(c for c, e in zip(cases, worst, strict=True) if e >= top * (1 - TIE))
    return Envelope(time_s, bands, len(cases)), CampaignWorst(
        folder=str(Path(folder).absolute()),
        cases=len(cases),
        worst_max_error_deg=top,
        worst_cases=tied,
    )


def write_worst_cases(
    folder: Path,
    model: Model,
    identity: WorstCaseIdentity,
    mu: ParametricMu | None,
    search: WorstCaseSearch | None,
    campaign: Path | None,
    *,
    with_plots: bool = True,
) -> WorstCaseSummary:
    """Write everything into the staging ``folder``; returns the summary (``campaign``: a
    finished corner campaign folder the search is compared with and drawn over)."""
    envelope, compared = (None, None) if campaign is None else corner_campaign_envelope(campaign)
    summary = worst_case_summary(identity, model.parameter_layout, mu, search, compared)
    write_worst_case_files(folder, model, summary, mu, search, envelope, with_plots)
    return summary


def worst_case_summary(
    identity: WorstCaseIdentity,
    layout: ParameterLayout,
    mu: ParametricMu | None,
    search: WorstCaseSearch | None,
    compared: CampaignWorst | None,
) -> WorstCaseSummary:
    """What ``summary.json`` holds: the identity, the mu bounds, the campaign compared
    with and the search, those that ran."""
    found = None if search is None else _search_summary(search, layout, compared)
    return WorstCaseSummary(identity, None if mu is None else mu.summary(), compared, found)


def write_worst_case_files(
    folder: Path,
    model: Model,
    summary: WorstCaseSummary,
    mu: ParametricMu | None,
    search: WorstCaseSearch | None,
    envelope: Envelope | None,
    with_plots: bool = True,
) -> None:
    """The parameter files, ``evaluations.csv``, ``worstcase.png`` (``with_plots``) and
    ``summary.json`` into the staging ``folder``."""
    problem = model.problem
    layout = model.parameter_layout
    if mu is not None:
        for kind in KINDS:
            worst = getattr(mu, kind).worst
            if worst is not None:
                values = parameters_from_normalized(model, worst.normalized)
                data = parameter_file(
                    layout, worst.normalized, values, f"mu-{kind}", perturbation=worst
                )
                write_json_atomic(folder / f"mu_{kind}_parameters.json", data)
    if search is not None:
        _write_search(folder, problem, search, layout, envelope, with_plots)
    write_json_atomic(folder / "summary.json", summary)


def worst_case_figure(
    problem: Problem, search: WorstCaseSearch, envelope: Envelope | None
) -> Figure:
    """The worst run found, over the corner campaign's ``envelope`` when given."""
    return closed_loop_figure(
        search.best_run,
        envelope=envelope,
        title=f"{problem.name}: worst case found, {search.best.max_error_deg:.4f} deg",
        **run_figures_options(problem),
    )


def _search_summary(
    search: WorstCaseSearch, layout: ParameterLayout, campaign: CampaignWorst | None
) -> SearchSummary:
    best = search.best
    return SearchSummary(
        max_error_deg=best.max_error_deg,
        source=best.source,
        evaluation=best.index,
        normalized=_named(layout, best.normalized),
        parameters=Parameters.from_vector(layout, best.parameters).to_dict(),
        simulations=search.simulations,
        screen_worst_corners=tuple(int(k) for k in search.screen_order[:5]),
        seed=search.seed,
        final_step=search.final_step,
        time_s=search.time_s,
        minus_campaign_worst_deg=None
        if campaign is None
        else best.max_error_deg - campaign.worst_max_error_deg,
    )


def _write_search(
    folder: Path,
    problem: Problem,
    search: WorstCaseSearch,
    layout: ParameterLayout,
    envelope: Envelope | None,
    with_plots: bool,
) -> None:
    best = search.best
    data = parameter_file(
        layout, best.normalized, best.parameters, "worstcase", max_error_deg=best.max_error_deg
    )
    write_json_atomic(folder / "worst_parameters.json", data)
    rows = np.array([e.normalized for e in search.evaluations])
    # A CSV table: its columns are the model's parameters, named at run time.
    columns: dict[str, np.ndarray] = {
        "evaluation": np.array([e.index for e in search.evaluations]),
        "source": np.array([e.source for e in search.evaluations]),
        "max_error_deg": np.array([e.max_error_deg for e in search.evaluations]),
    }
    for i, name in enumerate(layout.names):
        columns[f"normalized_{name}"] = rows[:, i]
    write_csv(folder / "evaluations.csv", columns)
    if with_plots:
        save_figure(worst_case_figure(problem, search, envelope), folder / "worstcase.png")
