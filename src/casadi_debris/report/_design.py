"""``report.md`` of ``casadi-debris design``: each figure of the design and its verification
beside the requirement it is judged against.

The requirements are the problem's ``[requirements]`` (pointing, slew error),
mu <= 1 (a guarantee at all), and conventional stability margins (6 dB and
30 deg over the sampled plants, no unstable sample).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.records import Record
from casadi_debris.report._common import format_figure, verdict_text
from casadi_debris.report._robust import MarginsSummary

# WorstValueSummary at run time: DesignSummary.from_json resolves its fields' types by name.
from casadi_debris.report._simulation import WorstValueSummary
from casadi_debris.robust.requirements import BindingLimit, BodySummary, ScalingSummary
from casadi_debris.robust.synthesis import DesignAttempt, DesignSearch

if TYPE_CHECKING:  # the campaign's module draws figures: imported by its callers
    from casadi_debris.report._simulation import CampaignSummary

GAIN_MARGIN_DB = 6.0
PHASE_MARGIN_DEG = 30.0
"""Conventional least margins of an attitude loop over the sampled plants."""


@dataclass(frozen=True)
class RequirementRow:
    """One figure against its requirement.

    Parameters
    ----------
    key : str
        Stable name for scripts (``"pointing_arcsec"``).
    result : str
        The row's title, with its unit.
    required : str
        The requirement as printed.
    ours : str
        Our figure as printed.
    values : tuple of float or None
        Our numbers, in the title's unit.
    met : bool or None
        Whether the requirement is met (None: shown, not judged).
    """

    key: str
    result: str
    required: str
    ours: str
    values: tuple[float | None, ...]
    met: bool | None

    @property
    def verdict(self) -> str:
        """✅/❌ with words, "—" when not judged."""
        return verdict_text(self.met, "met")

    def entry(self) -> RequirementEntry:
        """The row as ``summary.json`` holds it."""
        return RequirementEntry(
            key=self.key,
            result=self.result,
            required=self.required,
            ours=self.ours,
            verdict=self.verdict,
            met=self.met,
            values=self.values,
        )


@dataclass(frozen=True)
class RequirementEntry(Record):
    """A row of a design's ``summary.json``: :class:`RequirementRow` with its verdict as
    printed."""

    key: str
    result: str
    required: str
    ours: str
    verdict: str
    met: bool | None
    values: tuple[float | None, ...]


def _row(
    key: str, result: str, required: str, values: Any, met: bool | None, text: str | None = None
) -> RequirementRow:
    numbers = tuple(
        None if v is None else float(v) for v in np.ravel(np.asarray(values, dtype=object))
    )
    return RequirementRow(
        key,
        result,
        required,
        text or format_figure(values),
        numbers,
        None if met is None else bool(met),
    )


def _at_most(values: Any, bound: float) -> bool:
    numbers = np.ravel(np.asarray(values, dtype=object))
    return all(v is not None and float(v) <= bound for v in numbers)


def _nominal_and_worst(campaign: CampaignSummary, key: str) -> list[float | None]:
    """A figure of a campaign's nominal run and its worst corner."""
    return [campaign.nominal[key], campaign.worst[key].value]


def requirement_rows(
    problem: Problem,
    search: DesignSearch,
    margins: MarginsSummary,
    campaigns: dict[str, CampaignSummary],
    torque_limits_mNm: np.ndarray,
) -> list[RequirementRow]:
    """The design's table (margins as from :func:`~casadi_debris.workflows._margins.margins`,
    campaigns as from :func:`~casadi_debris.workflows._montecarlo.montecarlo`): the
    judged rows, then :func:`information_rows`."""
    chosen = search.chosen
    pointing_req = problem.requirements.pointing_arcsec
    guaranteed = chosen.guaranteed_pointing_arcsec
    orders = [search.design.musyn.controller.nstates, search.design.record.reduced.nstates]
    return [
        _row("mu_peak", "μ, full / reduced controller", "≤ 1",
             [chosen.mu_peak, chosen.mu_peak_reduced], chosen.mu_peak_reduced <= 1.0),
        _row("guaranteed_pointing_arcsec", "guaranteed pointing x / y / z [arcsec]",
             f"≤ {pointing_req:g}", list(guaranteed) if guaranteed else [None],
             guaranteed is not None and _at_most(guaranteed, pointing_req),
             None if guaranteed else "none (μ > 1)"),
        *verification_rows(problem, margins, campaigns, torque_limits_mNm, orders),
    ]  # fmt: skip


def verification_rows(
    problem: Problem,
    margins: MarginsSummary,
    campaigns: dict[str, CampaignSummary],
    torque_limits_mNm: np.ndarray,
    orders: list[int],
) -> list[RequirementRow]:
    """What any controller is judged on, whatever designed it: pointing and slew error
    over the corners against the requirements, margins over sampled plants, then
    :func:`information_rows` (``orders``: the controller's full and flown order)."""
    pointing_req = problem.requirements.pointing_arcsec
    slew_req = problem.requirements.slew_error_deg
    pointing = _nominal_and_worst(campaigns["pointing"], "max_error_arcsec")
    slew = _nominal_and_worst(campaigns["slew"], "max_error_deg")
    sampled = margins.sampled_min
    margin_values = [sampled.gain_margin_db, sampled.phase_margin_deg, sampled.delay_margin_s]
    unstable = margins.unstable_samples
    return [
        _row("pointing_arcsec", "pointing error, nominal / worst corner [arcsec]",
             f"≤ {pointing_req:g}", pointing, _at_most(pointing, pointing_req)),
        _row("slew_max_error_deg", "slew error, nominal / worst corner [deg]",
             f"≤ {slew_req:g}", slew, _at_most(slew, slew_req)),
        _row("margins_sampled", f"margins over {margins.samples} sampled plants [dB, deg, s]",
             f"≥ {GAIN_MARGIN_DB:g} dB, ≥ {PHASE_MARGIN_DEG:g}° (conventional)", margin_values,
             margin_values[0] >= GAIN_MARGIN_DB and margin_values[1] >= PHASE_MARGIN_DEG),
        _row("unstable_samples", "unstable sampled loops", "0", unstable, unstable == 0),
        *information_rows(campaigns, torque_limits_mNm, orders),
    ]  # fmt: skip


def information_rows(
    campaigns: dict[str, CampaignSummary], torque_limits_mNm: np.ndarray, orders: list[int]
) -> list[RequirementRow]:
    """Figures shown beside the requirements, not judged: torque use, fuel, settling, order."""
    torque_ratio = max(
        float(np.max(np.asarray(c.max_torque_mNm) / torque_limits_mNm)) for c in campaigns.values()
    )
    slew = campaigns["slew"]
    return [
        _row("torque_to_limit", "peak torque / authority, slew and pointing", "—",
             torque_ratio, None),
        _row("slew_fuel_kg", "slew propellant, nominal / worst corner [kg]", "—",
             _nominal_and_worst(slew, "fuel_kg"), None),
        _row("slew_settle_time_s", "settling time after the slew, worst corner [s]", "—",
             slew.worst["settle_time_s"].value, None),
        _row("controller_order", "controller order, full / reduced", "—", orders, None),
    ]  # fmt: skip


@dataclass(frozen=True)
class VerificationSummary(Record):
    """A verification campaign as a design summary gives it: its size, worst cases
    and nominal run (see :class:`~casadi_debris.report._simulation.CampaignSummary`)."""

    cases: int
    worst: dict[str, WorstValueSummary]
    nominal: dict[str, Any]


@dataclass(frozen=True)
class DesignSummary(Record):
    """A design's ``summary.json``: requirements met, the chosen controller's μ, the
    performance search and the verification campaigns.

    ``method`` is ``"mu"`` (D-K μ-synthesis), ``"pd"`` or ``"lqr"`` (see
    :mod:`casadi_debris.robust.synthesis`; their μ fields are None and ``attempts`` empty).
    ``requirements_met`` is True only when every judged requirement is met
    (``requirements_passed`` of ``requirements`` are); when it is False, ``binding``
    names each missed requirement's limit with its numbers and what would meet it
    (:mod:`casadi_debris.robust.requirements`), and the controller written is the best found.
    ``body`` holds the body figures the bandwidth and roll-off come from and where each
    came from (:mod:`casadi_debris.robust.requirements`).
    ``rows`` are the requirement rows (:meth:`RequirementRow.entry`);
    ``guaranteed_pointing_arcsec`` the pointing error μ guarantees per axis (None when
    μ > 1); ``scalings`` and ``attempts`` the derived weights and the search over the
    performance level; ``time_s`` the wall time [s].
    """

    problem: str
    problem_sha256: str
    plant_sha256: str
    requirements_met: bool
    requirements_passed: int
    requirements: int
    method: str
    mu_peak: float | None
    mu_peak_reduced: float | None
    guaranteed_pointing_arcsec: list[float] | None
    required_pointing_arcsec: Any
    scalings: ScalingSummary
    attempts: tuple[DesignAttempt, ...]
    seed: int | None
    slew: VerificationSummary
    pointing: VerificationSummary
    rows: tuple[RequirementEntry, ...]
    time_s: float
    out_dir: str
    quick: bool
    workers: int
    controller_path: str
    binding: tuple[BindingLimit, ...] = ()
    body: BodySummary | None = None


@dataclass(frozen=True)
class DesignFigures:
    """Figures of a design folder that exist, as (title, relative path)."""

    entries: tuple[tuple[str, str], ...]

    CANDIDATES = (
        ("Slew: error and torque, corner envelope shaded", "slew/envelope.png"),
        ("Pointing: error and torque, corner envelope shaded", "pointing/envelope.png"),
        ("μ of the robust-performance problem", "margins/mu.png"),
        ("Uncertainty weight W over the sampled relative errors", "margins/uncertainty_weight.png"),
        ("Loop shapes", "margins/loop_shapes.png"),
        ("Margins over sampled plants", "margins/margins.png"),
    )

    @classmethod
    def present_in(cls, folder: Path) -> DesignFigures:
        """The candidates found in ``folder``."""
        return cls(tuple((t, p) for t, p in cls.CANDIDATES if (folder / p).exists()))


def _attempts_table(search: DesignSearch) -> list[str]:
    lines = [
        "| Ve / required | Ve [deg] | μ full | μ reduced | guaranteed pointing [arcsec] "
        "| D-K steps |",
        "|---|---|---|---|---|---|",
    ]
    required_ve = search.scalings.error_deg[0] / search.scalings.ve_ratio
    for a in search.attempts:
        guaranteed = (
            "none (μ > 1)"
            if a.guaranteed_pointing_arcsec is None
            else format_figure(max(a.guaranteed_pointing_arcsec))
        )
        lines.append(
            f"| {a.ve_ratio:.3g} | {required_ve * a.ve_ratio:.4g} | {a.mu_peak:.4f} | "
            f"{a.mu_peak_reduced:.4f} | {guaranteed} | {a.iterations} |"
        )
    return lines


def design_markdown(
    problem: Problem,
    search: DesignSearch,
    rows: list[RequirementRow],
    summary: DesignSummary,
    figures: DesignFigures,
) -> str:
    """The report: requirements table, how the performance level was found, figures."""
    scalings = search.scalings
    lines = [
        f"# Controller design for {problem.name}",
        "",
        f"{headline(summary)} ({summary.time_s:.0f} s). Controller: `controller.json` "
        f"(plant sha256 {problem.plant_sha256[:12]}).",
        "",
        "| result | required | ours | verdict |",
        "|---|---|---|---|",
        *[f"| {r.result} | {r.required} | {r.ours} | {r.verdict} |" for r in rows],
        "",
        *binding_lines(summary.binding),
        "## Weights",
        "",
        *body_lines(summary.body),
        f"- Vu = {format_figure(scalings.control_mNm.tolist())} mNm: the torque authority "
        "per axis with zero net force (smaller sign).",
        f"- Vd = {format_figure(scalings.disturbance_mNm.tolist())} mNm: 1 % of Vu, shaped by "
        "the disturbance amplitudes.",
        f"- Ve = {format_figure(scalings.error_deg.tolist())} deg: {scalings.ve_ratio:.3g} x the "
        "level whose robust-performance bound is the pointing requirement.",
        f"- Vr = {format_figure(scalings.reference_deg.tolist())} deg: the reference the loop "
        "must follow: Ve, held at the requirement's Ve when Ve loosens beyond it (a looser "
        "Ve then cannot raise μ).",
        "",
        "The guaranteed pointing is the steady error under the problem's sine disturbance "
        "that μ ≤ 1 bounds for every plant the fitted uncertainty weight covers: "
        "μ Ve ‖Vd⁻¹ A‖ / |We(jω_d)| per axis. It holds for the sampled set as the weight "
        "covers it (a complex cover of real parameters: conservative), not for the "
        "transient of a slew, which the corner campaign checks.",
        "",
        "## Performance level",
        "",
        *_attempts_table(search),
        "",
    ]
    for title, path in figures.entries:
        lines += [f"## {title}", "", f"![{title}]({path})", ""]
    return "\n".join(lines)


def classical_markdown(
    problem: Problem,
    controller: dict[str, Any],
    rows: list[RequirementRow],
    summary: DesignSummary,
    figures: DesignFigures,
) -> str:
    """The report of a PD or LQG design: the same table, the controller's settings, figures.

    ``controller`` is the controller file's ``details`` (method and its settings).
    """
    settings = ", ".join(
        f"{k} = {format_figure(v)}" for k, v in controller.items() if k != "method"
    )
    lines = [
        f"# {summary.method.upper()} controller for {problem.name}",
        "",
        f"{headline(summary)} ({summary.time_s:.0f} s). Controller: `controller.json` "
        f"(plant sha256 {problem.plant_sha256[:12]}), designed on the rigid body; the "
        "flexible modes and the uncertainty are judged by the margins and the corners below.",
        "",
        "| result | required | ours | verdict |",
        "|---|---|---|---|",
        *[f"| {r.result} | {r.required} | {r.ours} | {r.verdict} |" for r in rows],
        "",
        f"Settings: {settings}.",
        "",
        *binding_lines(summary.binding),
    ]
    for title, path in figures.entries:
        lines += [f"## {title}", "", f"![{title}]({path})", ""]
    return "\n".join(lines)


def headline(summary: DesignSummary) -> str:
    """ "All N requirements met", or how many were and that the controller is the best found."""
    if summary.requirements_met:
        return f"All {summary.requirements} requirements met"
    return (
        f"Requirements NOT met: {summary.requirements_passed} of {summary.requirements}; "
        "the controller written is the best found, not one that meets them"
    )


def binding_lines(binding: tuple[BindingLimit, ...]) -> list[str]:
    """The report's section on the limits that bind (none when every requirement is met)."""
    if not binding:
        return []
    lines = ["## What binds", ""]
    for limit in binding:
        lines.append(f"- **{limit.requirement}**: {limit.limit}. What would meet it:")
        lines += [f"    - {remedy}" for remedy in limit.remedies]
    lines += [
        "",
        "The remedies are estimates from scaling laws (see `casadi_debris.robust.requirements`); "
        "design again to confirm.",
        "",
    ]
    return lines


def body_lines(body: BodySummary | None) -> list[str]:
    """How the bandwidth and roll-off were chosen, with the body figures behind them."""
    if body is None:
        return ["- We and Wu: the problem's `[weights]`.", ""]
    origin = {
        "derived": "derived from this body",
        "problem": "the problem's own `[weights]`",
        "paper": "the paper's, tuned for this (the paper's) body",
    }
    hold = ", ".join(f"{w:.3g}" for w in body.hold_bandwidth_rad_s)
    mode = (
        "no flexible mode: a tenth of the slower of the star tracker and the control "
        "loop's Nyquist frequency"
        if body.first_mode_rad_s is None
        else f"1.2 times below the lowest first bending frequency, {body.first_mode_rad_s:.3g} "
        "rad/s"
    )
    lines = [
        f"- We bandwidth {body.bandwidth_rad_s:.4g} rad/s, {origin[body.bandwidth_from]}. "
        f"The rule: per axis sqrt((τ − A) / (J e_slew)), the stiffness at which the torque "
        f"left by the disturbance answers the allowed slew error, = {hold} rad/s (J = "
        f"{format_figure(list(body.inertia_kgm2))} kg m², τ = "
        f"{format_figure(list(body.authority_mNm))} mNm, A = "
        f"{format_figure(list(body.disturbance_mNm))} mNm); the smallest, at most 1/30 of the "
        f"roll-off: {body.derived_bandwidth_rad_s:.4g} rad/s.",
        f"- Wu roll-off {body.rolloff_rad_s:.4g} rad/s, {origin[body.rolloff_from]}. The rule: "
        f"{mode}: {body.derived_rolloff_rad_s:.4g} rad/s.",
    ]
    inherited = [
        (name, used, paper)
        for name, used, paper, origin_ in (
            ("bandwidth", body.bandwidth_rad_s, body.paper_bandwidth_rad_s, body.bandwidth_from),
            ("roll-off", body.rolloff_rad_s, body.paper_rolloff_rad_s, body.rolloff_from),
        )
        if origin_ == "derived" and used != paper
    ]
    for name, used, paper in inherited:
        lines.append(
            f"- The paper's {name} ({paper:.4g} rad/s, inherited through `extends`) was tuned "
            f"for another body; this design uses {used:.4g} rad/s."
        )
    return [*lines, ""]
