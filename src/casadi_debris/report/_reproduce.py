"""``report.md`` of ``casadi-debris reproduce``: every figure of the paper next to ours.

The rows are the paper's figures of ``data/paper_reference.toml`` (paper value,
accepted tolerance, ours, verdict); the figures are the paper's Figs. 4 and 5
redrawn from our closed loop with the Monte-Carlo envelope, and the
robust-control plots.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from casadi_debris.records import Record
from casadi_debris.report._common import format_figure, verdict_text
from casadi_debris.report._describe import ModelSummary
from casadi_debris.report._paper import paper_figure
from casadi_debris.report._robust import MarginsSummary
from casadi_debris.robust.plant import Controller

if TYPE_CHECKING:  # the campaign's module draws figures: imported by its callers
    from casadi_debris.report._simulation import CampaignSummary


@dataclass(frozen=True)
class ReproductionRow:
    """One row of the reproduction table: a figure of the paper against ours.

    Parameters
    ----------
    key : str
        The figure's key in ``data/paper_reference.toml`` (``"mass_kg"``).
    result : str
        The row's title, with its unit (``"total mass [kg]"``).
    paper : str
        The paper's figure as printed.
    accepted : str
        The tolerance as printed.
    ours : str
        Our figure as printed.
    ours_values : tuple of float or None
        Our numbers, one per component of the paper's figure, in its unit
        (None: not computed, e.g. a controller file without its full order).
    reproduced : bool or None
        Whether ours are within the tolerance (None: not judged).
    """

    key: str
    result: str
    paper: str
    accepted: str
    ours: str
    ours_values: tuple[float | None, ...]
    reproduced: bool | None

    @property
    def verdict(self) -> str:
        """The verdict as printed: ✅/❌ with words, "—" when not judged."""
        return verdict_text(self.reproduced, "reproduced")

    def entry(self) -> TableEntry:
        """The row as ``summary.json``'s table holds it."""
        return TableEntry(
            key=self.key,
            result=self.result,
            paper=self.paper,
            accepted=self.accepted,
            ours=self.ours,
            verdict=self.verdict,
            reproduced=self.reproduced,
            ours_values=self.ours_values,
        )


@dataclass(frozen=True)
class TableEntry(Record):
    """A row of ``summary.json``'s table: ``result``, ``paper``, ``accepted``, ``ours`` and
    ``verdict`` as printed; ``reproduced`` true, false or null (not judged); the figure's
    ``key`` and ``ours_values`` (see :class:`ReproductionRow`)."""

    key: str
    result: str
    paper: str
    accepted: str
    ours: str
    verdict: str
    reproduced: bool | None
    ours_values: tuple[float | None, ...]


@dataclass(frozen=True)
class ReproductionSummary(Record):
    """A reproduction's ``summary.json``: the table and how the run was made.

    ``table`` holds the rows as :meth:`ReproductionRow.entry` gives them;
    ``reproduced`` counts the rows within tolerance, of ``rows``; ``time_s`` is the
    wall time [s].
    """

    problem: str
    problem_sha256: str
    controller_path: str
    quick: bool
    workers: int
    time_s: float
    reproduced: int
    rows: int
    table: tuple[TableEntry, ...]
    out_dir: str


def paper_row(key: str, ours: Any, text: str | None = None, **title_fields: Any) -> ReproductionRow:
    """The row of the paper's figure ``key`` for our number(s) ``ours``.

    Parameters
    ----------
    key : str
        A figure of ``data/paper_reference.toml``.
    ours : float or sequence of float
        One number per component of the figure, in its unit.
    text : str, optional
        Our figure as printed (default: the numbers, " / " between them).
    **title_fields
        Fields of the title (``samples`` of ``margins_sampled``).
    """
    figure = paper_figure(key)
    values = tuple(
        None if v is None else float(v) for v in np.ravel(np.asarray(ours, dtype=object))
    )
    return ReproductionRow(
        key=key,
        result=figure.title.format(**title_fields),
        paper=figure.paper,
        accepted=figure.accepted,
        ours=format_figure(ours) if text is None else text,
        ours_values=values,
        reproduced=figure.accepts(values),
    )


BUDGET_KEYS = (
    "dv_one_stage_one_face_m_s",
    "dv_three_stages_one_face_m_s",
    "dv_one_stage_all_faces_m_s",
    "dv_all_stages_all_faces_m_s",
    "dv_cubesat_one_stage_m_s",
    "dv_transfer_m_s",
    "detumble_time_h",
)


def model_rows(model: ModelSummary) -> list[ReproductionRow]:
    """Mass, inertia and torque authority of the combined system."""
    torque = model.torque_max_mNm
    # The paper gives one authority per axis: the smaller of + and - is what
    # the controller can count on.
    torque_axes = [min(torque[f"+{a}"], torque[f"-{a}"]) for a in "xyz"]
    inertia = np.diag(np.asarray(model.inertia_hub_cubesats_kgm2))
    return [
        paper_row("mass_kg", model.mass_kg),
        paper_row("inertia_hub_cubesats_diag_kgm2", inertia.tolist()),
        paper_row("torque_max_mNm", torque_axes),
    ]


def budget_rows(budgets: dict[str, float]) -> list[ReproductionRow]:
    """Δv, transfer and detumble budgets (``budgets`` keyed as the figures, m/s and h)."""
    return [paper_row(key, budgets[key]) for key in BUDGET_KEYS]


@dataclass(frozen=True)
class ControllerSummary:
    """What the reproduction reads of a controller: peak μ of the full and the reduced
    loop, and their orders (``order_full`` None for a file without its full order)."""

    mu_peak: float | None
    mu_peak_reduced: float | None
    order_full: int | None
    order_reduced: int

    @classmethod
    def of(cls, record: Controller) -> ControllerSummary:
        """The figures of a controller file."""
        return cls(
            mu_peak=record.mu_peak,
            mu_peak_reduced=record.mu_peak_reduced,
            order_full=None if record.full is None else record.full.nstates,
            order_reduced=record.reduced.nstates,
        )


def controller_rows(controller: ControllerSummary) -> list[ReproductionRow]:
    """Peak μ and order of the controller."""
    return [
        paper_row("mu_peak", [controller.mu_peak, controller.mu_peak_reduced]),
        paper_row("controller_order", [controller.order_full, controller.order_reduced]),
    ]


def margin_rows(margins: MarginsSummary) -> list[ReproductionRow]:
    """Nominal and sampled loop-at-a-time margins (dB, deg, s)."""
    nominal, sampled = margins.nominal, margins.sampled_min
    return [
        paper_row("margins_nominal", [nominal.gain_margin_db, nominal.phase_margin_deg]),
        paper_row(
            "margins_sampled",
            [sampled.gain_margin_db, sampled.phase_margin_deg, sampled.delay_margin_s],
            samples=margins.samples,
        ),
    ]


def slew_rows(slew: CampaignSummary, duration_s: float | None) -> list[ReproductionRow]:
    """The 180° slew: nominal error and fuel, reference duration, corner envelope.

    ``slew`` is the slew campaign's summary (deg, kg); ``duration_s`` the slew's
    reference duration [s].
    """
    nominal = slew.nominal
    worst = format_figure(slew.worst["max_error_deg"].value)
    return [
        paper_row("slew_max_error_deg", nominal["max_error_deg"]),
        paper_row("slew_fuel_kg", nominal["fuel_slew_kg"]),
        paper_row("slew_duration_s", duration_s),
        paper_row(
            "slew_envelope_cases",
            slew.cases,
            text=f"{slew.cases} (worst error {worst}°)",
        ),
    ]


def pointing_rows(
    pointing: CampaignSummary, torque_limits_mNm: np.ndarray
) -> list[ReproductionRow]:
    """One orbit of pointing: error nominal and at the worst corner, torque within limits.

    Parameters
    ----------
    pointing : CampaignSummary
        The pointing campaign's summary (arcsec, mNm).
    torque_limits_mNm : ndarray, shape (3,)
        The torque authority per axis [mNm].
    """
    nominal = pointing.nominal["max_error_arcsec"]
    worst = pointing.worst["max_error_arcsec"].value
    torque_to_limit = float(np.max(np.asarray(pointing.max_torque_mNm) / torque_limits_mNm))
    return [
        paper_row(
            "pointing",
            [nominal, worst, pointing.cases, torque_to_limit],
            text=f"{format_figure(nominal)} / {format_figure(worst)} ({pointing.cases} cases)",
        )
    ]


def reproduction_rows(
    model: ModelSummary,
    budgets: dict[str, float],
    controller: ControllerSummary,
    margins: MarginsSummary,
    slew: CampaignSummary,
    slew_duration_s: float | None,
    pointing: CampaignSummary,
    torque_limits_mNm: np.ndarray,
) -> list[ReproductionRow]:
    """The reproduction table, one row per figure of the paper, in the paper's order.

    See :func:`model_rows`, :func:`budget_rows`, :func:`controller_rows`,
    :func:`margin_rows`, :func:`slew_rows` and :func:`pointing_rows` for what
    each argument holds.
    """
    return [
        *model_rows(model),
        *budget_rows(budgets),
        *controller_rows(controller),
        *margin_rows(margins),
        *slew_rows(slew, slew_duration_s),
        *pointing_rows(pointing, torque_limits_mNm),
    ]


PAPER_CURVES_NOTE = (
    "The paper's curves are not drawn beside ours: its slew and pointing result figures "
    "plot data files its source does not include (`figures/SlewDataNL.csv`, "
    "`figures/SlewBounds.csv`, `figures/PointDataNL.csv`), so they are compared by the "
    "figures the paper states (the table above), not curve by curve."
)


def report_markdown(
    rows: list[ReproductionRow],
    summary: ReproductionSummary,
    figures: list[tuple[str, str]],
) -> str:
    """The whole ``report.md``."""
    lines = [
        "# casadi_debris: reproduction of the reference paper",
        "",
        f"Problem `{summary.problem}` (sha256 `{summary.problem_sha256[:12]}…`), "
        f"controller `{Path(summary.controller_path).name}`, "
        f"{'quick run (reduced samples and corners)' if summary.quick else 'full run'}, "
        f"{summary.time_s:.0f} s on {summary.workers} worker(s).",
        "",
        "| result | paper | accepted | ours | verdict |",
        "| --- | --- | --- | --- | --- |",
        *(
            f"| {row.result} | {row.paper} | {row.accepted} | {row.ours} | {row.verdict} |"
            for row in rows
        ),
        "",
        "A quick run reduces the margin samples and corner cases, so the rows that need",
        "every corner read ❌ there by design; `casadi-debris reproduce` without `--quick`",
        "runs them all.",
        "",
        PAPER_CURVES_NOTE,
        "",
    ]
    for title, path in figures:
        lines += [f"## {title}", "", f"![{title}]({path})", ""]
    return "\n".join(lines)
