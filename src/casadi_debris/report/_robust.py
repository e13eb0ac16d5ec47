"""Margins of a controller: the summary, the figures and the run folder
(``casadi-debris margins``)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, cast

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.dynamics import build_model, linearize
from casadi_debris.plots import (
    loop_shapes_figure,
    margins_figure,
    mu_figure,
    save_figure,
    uncertainty_weight_figure,
)
from casadi_debris.records import Record
from casadi_debris.report._paper import paper_figure
from casadi_debris.robust.margins import (
    MarginStudy,
    loop_shapes,
    margins_table,
    sampled_loop_at_a_time,
)
from casadi_debris.robust.plant import (
    Controller,
    diagonal_cover,
    frequency_response,
    generalized_plant,
    recorded_performance_weights,
    relative_errors,
    sample_uncertainty,
    weight_system,
)
from casadi_debris.robust.synthesis import closed_loop_mu, weight_fit_grid
from casadi_debris.store import write_json_atomic

if TYPE_CHECKING:
    from matplotlib.figure import Figure

MARGINS = ("gain_margin_db", "phase_margin_deg", "delay_margin_s")


def paper_margins() -> dict[str, float]:
    """The paper's margins (dB, deg, s): ``nominal_*`` and ``sampled_min_*``."""
    return {
        f"{prefix}_{c.name}": c.value
        for prefix, key in (("nominal", "margins_nominal"), ("sampled_min", "margins_sampled"))
        for c in paper_figure(key).components
    }


def required_margins() -> dict[str, float]:
    """The least margins accepted over the sampled plants (dB, deg, s), by name."""
    return {
        c.name: float(cast(float, c.tolerance.bound))
        for c in paper_figure("margins_sampled").components
        if c.tolerance is not None
    }


@dataclass(frozen=True)
class Margins(Record):
    """Gain, phase and delay margins [dB, deg, s] (the worst over channels or plants)."""

    gain_margin_db: float
    phase_margin_deg: float
    delay_margin_s: float

    @classmethod
    def worst(cls, margins: dict[str, dict[str, float]]) -> Margins:
        """The smallest of each margin over the channels of ``margins``."""
        return cls(**{key: min(channel[key] for channel in margins.values()) for key in MARGINS})


@dataclass(frozen=True)
class DiskMargin(Record):
    """The disk margin: skew-free alpha and the gain and phase it guarantees."""

    alpha: float
    gain_margin_db: float
    phase_margin_deg: float


@dataclass(frozen=True, kw_only=True)
class MarginsSummary(Record):
    """Margins of a controller on a problem, nominal and over sampled plants.

    Attributes
    ----------
    problem, problem_sha256, plant_sha256 : str
    controller_path : str
    controller_order : int
    controller_plant_sha256 : str
        The plant the controller was designed for ("" when its file records none).
    analysis_plant_modes : str
        The array modes of the plants analysed.
    nominal, sampled_min : Margins
        Worst over the channels; over the stable sampled plants too.
    nominal_sampled_data : Margins
        The nominal loop as flown: plant and controller held and sampled at the
        problem's control rate (worst over the channels).
    control_rate_hz : float
    per_channel : dict
        ``"x"``, ``"y"``, ``"z"`` -> gain (and its upper and lower), phase and delay
        margins and the crossover of that loop, the others closed.
    disk_margin : DiskMargin
    samples, corner_samples, unstable_samples, seed : int
    time_s : float
        Wall time of the study.
    required, paper : dict of str to float
        The margins accepted over the sampled plants, and the paper's.
    out_dir : str or None
        The folder it was written to (None until it is).
    """

    problem: str
    problem_sha256: str
    controller_path: str
    controller_order: int
    plant_sha256: str
    controller_plant_sha256: str
    analysis_plant_modes: str
    nominal: Margins
    sampled_min: Margins
    nominal_sampled_data: Margins
    control_rate_hz: float
    per_channel: dict[str, dict[str, float]]
    disk_margin: DiskMargin
    samples: int
    corner_samples: int
    unstable_samples: int
    seed: int
    time_s: float
    required: dict[str, float]
    paper: dict[str, float]
    out_dir: str | None = None


def margins_summary(
    problem: Problem, record: Controller, controller_path: Path, study: MarginStudy
) -> MarginsSummary:
    """What ``summary.json`` holds of a margin study of ``record`` (flown from
    ``controller_path``) on ``problem``; ``out_dir`` is None until it is written."""
    per_channel = margins_table(study.nominal)
    alpha, disk_gain_db, disk_phase_deg = study.nominal_disk
    return MarginsSummary(
        problem=problem.name,
        problem_sha256=problem.sha256,
        controller_path=str(controller_path),
        controller_order=record.reduced.nstates,
        plant_sha256=problem.plant_sha256,
        controller_plant_sha256=record.problem_sha256,
        analysis_plant_modes=study.modes,
        nominal=Margins.worst(per_channel),
        sampled_min=Margins(**study.sampled_min()),
        nominal_sampled_data=_sampled_data_margins(problem, record, study.modes),
        control_rate_hz=problem.simulation.control_rate_hz,
        per_channel=per_channel,
        disk_margin=DiskMargin(alpha, disk_gain_db, disk_phase_deg),
        samples=len(study.samples.parameters),
        corner_samples=study.samples.n_corners,
        unstable_samples=int(study.unstable.sum()),
        seed=study.samples.seed,
        time_s=study.time_s,
        required=required_margins(),
        paper=paper_margins(),
    )


def write_margins(
    folder: Path,
    summary: MarginsSummary,
    study: MarginStudy,
    figures: dict[str, Figure] | None,
) -> None:
    """A margin study into ``folder`` (a staging folder the caller owns): ``summary.json``,
    ``sampled_margins.csv`` and the ``figures`` (of :func:`margin_figures`; None: none)."""
    staging = Path(folder)
    staging.mkdir(parents=True, exist_ok=True)
    write_json_atomic(staging / "summary.json", summary)
    header = "sample," + ",".join(
        f"{q}_{a}" for a in "xyz" for q in ("gain_margin_db", "phase_margin_deg", "delay_margin_s")
    )
    rows = np.column_stack(
        [np.arange(len(study.sampled)), study.sampled.reshape(len(study.sampled), 9)]
    )
    np.savetxt(staging / "sampled_margins.csv", rows, delimiter=",", header=header, comments="")
    for name, figure in (figures or {}).items():
        save_figure(figure, staging / f"{name}.png")


def _sampled_data_margins(problem: Problem, record: Controller, modes: str) -> Margins:
    """The nominal loop's margins held and sampled at the problem's control rate."""
    plant = linearize(build_model(problem, modes=modes), sensor=True, units="deg_mNm")
    period_s = 1.0 / problem.simulation.control_rate_hz
    per_channel = margins_table(sampled_loop_at_a_time(plant, record.reduced, period_s))
    return Margins.worst(per_channel)


def margin_figures(problem: Problem, record: Controller, study: MarginStudy) -> dict[str, Figure]:
    """The figures of a margin study by file stem: ``mu``, ``uncertainty_weight`` and
    ``loop_shapes`` (when the controller records its uncertainty weight, as a μ design
    does) and ``margins`` (gain against phase margin of every sampled plant)."""
    figures: dict[str, Figure] = {}
    weight_info = record.details.get("uncertainty_weight", {})
    coefficients = np.array(weight_info.get("coefficients_k_wz_zetaz_wp_zetap", []))
    design_model = build_model(problem, modes=record.details.get("design_plant_modes", "first"))
    design_plant = linearize(design_model, sensor=True, units="deg_mNm")
    omega = np.logspace(-4, 2, 300)
    if coefficients.shape == (3, 5):
        weight = weight_system(coefficients)
        weights = recorded_performance_weights(problem, record.details.get("weights", {}))
        plant = generalized_plant(design_plant, weight, weights)
        curves = {}
        if record.full is not None:
            curves[f"full order ({record.full.nstates})"] = closed_loop_mu(
                plant, record.full, omega
            )[1].mu
        curves[f"reduced ({record.reduced.nstates})"] = closed_loop_mu(
            plant, record.reduced, omega
        )[1].mu
        figures["mu"] = mu_figure(omega, curves)
        count = int(weight_info.get("samples", problem.uncertainty.samples))
        samples = sample_uncertainty(design_model, count, record.seed)
        grid = weight_fit_grid(problem)
        bound = diagonal_cover(relative_errors(design_model, samples.parameters, grid))
        response = np.abs(np.diagonal(frequency_response(weight, grid), axis1=1, axis2=2))
        figures["uncertainty_weight"] = uncertainty_weight_figure(grid, bound, response, count)
        we = np.abs(frequency_response(weights.error, omega)[:, 0, 0])
        w_max = np.max(
            np.abs(np.diagonal(frequency_response(weight, omega), axis1=1, axis2=2)), axis=1
        )
        s_values, t_values = loop_shapes(design_plant, record.reduced, omega)
        figures["loop_shapes"] = loop_shapes_figure(omega, s_values, t_values, 1 / we, 1 / w_max)
    nominal = np.array(
        [[m.gain_margin_db, m.phase_margin_deg, m.delay_margin_s] for m in study.nominal]
    )
    required = required_margins()
    stable = study.sampled[~study.unstable]
    figures["margins"] = margins_figure(
        stable, nominal, (required["gain_margin_db"], required["phase_margin_deg"])
    )
    return figures
