"""The mission as a run folder (``casadi-debris mission``).

Files: ``summary.json`` (:class:`~casadi_debris.studies.mission.MissionSummary`),
``phases.csv`` (the timeline), ``propellant.csv`` (per CubeSat, stage and phase, g,
with each stage's capacity and what is left), ``mission.png`` (timeline, and propellant
per CubeSat and stage stacked by phase), ``altitude.png`` (mean altitude and perigee per
solar case from the start of the transfer) and ``decay.png`` (perigee and apogee per
solar case, from the burn's start); every figure also as PDF.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import TYPE_CHECKING, Any

from casadi_debris.orbit import DV_SEARCH_MAX_M_S
from casadi_debris.report._common import format_table
from casadi_debris.store import write_json_atomic
from casadi_debris.studies.mission import MAX_EXTRA_STAGES, Mission, MissionSummary
from casadi_debris.units import G_PER_KG

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def write_mission(folder: Path, mission: Mission, *, plots: bool = True) -> None:
    """Every file of the run folder (see the module's text); the figures with ``plots``."""
    summary = mission.summary
    write_json_atomic(folder / "summary.json", summary)
    with (folder / "phases.csv").open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["phase", "start_days", "duration_days", "dv_m_s", "propellant_kg", "note"])
        for p in summary.phases:
            writer.writerow(
                [p.name, p.start_days, p.duration_days, p.dv_m_s, p.propellant_kg, p.note]
            )
    with (folder / "propellant.csv").open("w", newline="") as handle:
        writer = csv.writer(handle)
        phases = [book.phase.replace(" ", "_") + "_g" for book in summary.books]
        writer.writerow(["cubesat", "stage", "capacity_g", *phases, "left_g"])
        for k, capacity in enumerate(summary.capacity_per_stage_kg):
            for s, full in enumerate(capacity):
                burnt = [book.per_stage_kg[k][s] for book in summary.books]
                left = full - sum(burnt)
                writer.writerow([k + 1, s + 1, *(G_PER_KG * v for v in (full, *burnt, left))])
    if plots:
        from casadi_debris.plots import save_figure

        for stem, figure in mission_figures(mission).items():
            save_figure(figure, folder / f"{stem}.png")


def mission_figures(mission: Mission) -> dict[str, Figure]:
    """``mission`` (timeline and propellant per stage), ``altitude`` (mean altitude and
    perigee per solar case) and ``decay`` (from the burn's start), by file stem."""
    from casadi_debris.plots import altitude_figure, decay_figure, mission_figure

    summary = mission.summary
    return {
        "mission": mission_figure(summary),
        "altitude": altitude_figure(summary, mission.trajectories),
        "decay": decay_figure(
            mission.trajectories, title=summary.problem, limit_years=summary.limit_years
        ),
    }


def mission_text(summary: MissionSummary, horizon_years: float) -> str:
    """The mission in plain text: the timeline, each solar case's re-entry, the verdict,
    what would close a gap and where the propellant went.

    ``horizon_years`` is how long the decay was flown (a re-entry later than that is
    said to be beyond it).
    """
    rows: list[list[Any]] = [
        [p.name, p.start_days, p.duration_days, p.dv_m_s, p.propellant_kg] for p in summary.phases
    ]
    headers = ["phase", "start [d]", "duration [d]", "dv [m/s]", "propellant [kg]"]
    lines = [format_table(headers, rows)]
    lines += [_case_sentence(summary, case, horizon_years) for case in summary.reentry_years]
    lines += [_verdict(summary), *_remedy(summary)]
    lines.append(
        f"Propellant: {summary.propellant_used_kg:.3f} of {summary.propellant_total_kg:.3f} kg"
        f" used; {summary.propellant_stranded_kg:.3f} kg stranded (no torque-free mix of the"
        " engines can burn it)."
    )
    return "\n".join(lines)


def _case_sentence(summary: MissionSummary, case: str, horizon_years: float) -> str:
    """One solar case: the Δv the rule needs, what the swarm flies, and when it re-enters."""
    limit = f"{summary.limit_years:g} years"
    left = summary.deorbit_dv_available_m_s
    need = summary.deorbit_dv_needed_m_s[case]
    years = summary.reentry_years[case]
    if years is None:
        when = f"stays up beyond the {horizon_years:g}-year horizon"
    else:
        when = f"re-enters {years:.2f} years after the burn starts"
    if need is None:
        return (
            f"{case.capitalize()} solar activity: no Δv up to {DV_SEARCH_MAX_M_S:g} m/s brings"
            f" re-entry within {limit}; burning all {left:.1f} m/s left, the debris {when}."
        )
    if need <= 0.0:
        return f"{case.capitalize()} solar activity: no burn needed; the debris {when}."
    if need > left * (1.0 + 1e-9):
        return (
            f"{case.capitalize()} solar activity: re-entry within {limit} needs {need:.1f} m/s,"
            f" more than the {left:.1f} m/s left; burning it all, the debris {when}."
        )
    return (
        f"{case.capitalize()} solar activity: re-entry within {limit} needs {need:.1f} m/s"
        f" of the {left:.1f} m/s left; burning that, the debris {when}."
    )


def _verdict(summary: MissionSummary) -> str:
    """Whether the mission meets the rule, and the Δv the transfer and detumble leave."""
    left, capacity = summary.deorbit_dv_available_m_s, summary.deorbit_dv_capacity_m_s
    budget = (
        f"the transfer and detumble leave {left:.1f} m/s of the {capacity:.1f} m/s that full"
        " tanks would give the deorbit"
    )
    if summary.meets_five_year_rule:
        return f"Meets the {summary.limit_years:g}-year rule under every solar case: {budget}."
    return (
        f"Does NOT meet the {summary.limit_years:g}-year rule (governing case: "
        f"{summary.governing_case} solar activity): {budget}."
    )


def _remedy(summary: MissionSummary) -> list[str]:
    """What would close the gap, when there is one."""
    extra = summary.extra_stages_needed
    if summary.meets_five_year_rule or extra == 0:
        return []
    if extra is None:
        return [
            f"Even {MAX_EXTRA_STAGES} more stages on every engine would not meet it: the swarm"
            " itself must change (more CubeSats or stronger engines)."
        ]
    stages = "one more stage" if extra == 1 else f"{extra} more stages"
    return [f"With {stages} on every engine it would meet the rule."]
