"""Worst cases as a run folder (``casadi-debris worstcase``): the mu bounds, the search,
parameter files ``simulate --parameters`` runs, and the worst run over a corner envelope.

Files: ``summary.json``; ``worst_parameters.json`` (the search's worst case),
``mu_performance_parameters.json`` and ``mu_stability_parameters.json`` (the
lower bounds' perturbations clipped to the box); ``evaluations.csv`` (every
simulation of the search); ``worstcase.png`` (the worst run, over the corner
campaign's envelope when one is given).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.model import Model, ParameterLayout, Parameters
from casadi_debris.plots.simulation import plot_closed_loop
from casadi_debris.report.common import write_csv, write_json_atomic
from casadi_debris.report.simulation import run_figures_options
from casadi_debris.robust.parametric_mu import ParametricMu
from casadi_debris.robust.uncertainty import parameters_from_normalized
from casadi_debris.simulation import Envelope
from casadi_debris.simulation.monte_carlo import Bands, Extremes
from casadi_debris.simulation.worst_case import WorstCaseSearch

# Campaign cases this close to the worst count as tied with it.
TIE = 1e-9


def parameter_file(
    layout: ParameterLayout, normalized: np.ndarray, values: np.ndarray, case_id: str, **extra: Any
) -> dict[str, Any]:
    """What a parameters file holds: ``parameters`` by name (SI) and their box positions."""
    named = Parameters.from_vector(layout, values).to_dict()
    return {
        "case_id": case_id,
        "parameters": named,
        "normalized": dict(zip(layout.names, np.asarray(normalized).tolist(), strict=True)),
        **extra,
    }


def campaign_envelope(folder: Path) -> tuple[Envelope, dict[str, Any]]:
    """A finished corner campaign's envelope and its worst case(s)."""
    from casadi_debris.report.campaign_dataset import open_campaign

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
    tied = [c for c, e in zip(cases, worst, strict=True) if e >= top * (1 - TIE)]
    return Envelope(time_s, bands, len(cases)), {
        "folder": str(Path(folder).absolute()),
        "cases": len(cases),
        "worst_max_error_deg": top,
        "worst_cases": tied,
    }


def write_worst_cases(
    folder: Path,
    problem: Problem,
    model: Model,
    identity: dict[str, Any],
    mu: ParametricMu | None,
    search: WorstCaseSearch | None,
    campaign: Path | None,
) -> dict[str, Any]:
    """Write everything into the staging ``folder``; returns the summary.

    ``identity`` holds what names the run (problem, controller, plants, out_dir).
    """
    layout = model.parameter_layout
    summary: dict[str, Any] = dict(identity)
    if mu is not None:
        summary["mu"] = mu.summary()
        for kind in ("stability", "performance"):
            worst = getattr(mu, kind).worst
            if worst is not None:
                values = parameters_from_normalized(problem, model, worst.normalized)
                data = parameter_file(
                    layout,
                    worst.normalized,
                    values,
                    f"mu-{kind}",
                    clipped=worst.clipped,
                    normalized_unclipped=dict(
                        zip(layout.names, worst.normalized_unclipped.tolist(), strict=True)
                    ),
                    mu_lower=worst.mu_lower,
                    omega_rad_s=worst.omega_rad_s,
                )
                write_json_atomic(folder / f"mu_{kind}_parameters.json", data)
    envelope = None
    if campaign is not None:
        envelope, summary["campaign"] = campaign_envelope(campaign)
    if search is not None:
        summary["search"] = _search_summary(search, layout, summary.get("campaign"))
        _write_search(folder, problem, search, layout, envelope)
    write_json_atomic(folder / "summary.json", summary)
    return summary


def _search_summary(
    search: WorstCaseSearch, layout: ParameterLayout, campaign: dict[str, Any] | None
) -> dict[str, Any]:
    best = search.best
    out: dict[str, Any] = {
        "max_error_deg": best.max_error_deg,
        "source": best.source,
        "evaluation": best.index,
        "normalized": dict(zip(layout.names, best.normalized.tolist(), strict=True)),
        "parameters": Parameters.from_vector(layout, best.parameters).to_dict(),
        "simulations": search.simulations,
        "screen_worst_corners": [int(k) for k in search.screen_order[:5]],
        "seed": search.seed,
        "final_step": search.final_step,
        "time_s": search.time_s,
        "local_search": True,
    }
    if campaign is not None:
        out["minus_campaign_worst_deg"] = best.max_error_deg - campaign["worst_max_error_deg"]
    return out


def _write_search(
    folder: Path,
    problem: Problem,
    search: WorstCaseSearch,
    layout: ParameterLayout,
    envelope: Envelope | None,
) -> None:
    best = search.best
    data = parameter_file(
        layout, best.normalized, best.parameters, "worstcase", max_error_deg=best.max_error_deg
    )
    write_json_atomic(folder / "worst_parameters.json", data)
    rows = np.array([e.normalized for e in search.evaluations])
    columns: dict[str, Any] = {
        "evaluation": np.array([e.index for e in search.evaluations]),
        "source": np.array([e.source for e in search.evaluations]),
        "max_error_deg": np.array([e.max_error_deg for e in search.evaluations]),
    }
    for i, name in enumerate(layout.names):
        columns[f"normalized_{name}"] = rows[:, i]
    write_csv(folder / "evaluations.csv", columns)
    plot_closed_loop(
        search.best_run,
        folder / "worstcase.png",
        envelope=envelope,
        title=f"{problem.name}: worst case found, {best.max_error_deg:.4f} deg",
        **run_figures_options(problem),
    )
