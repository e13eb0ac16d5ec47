"""Swarm designs side by side as a run folder (``casadi-debris alternatives``).

Files: ``summary.json`` (every design's :class:`~casadi_debris.studies.alternatives.SwarmSummary`),
``alternatives.csv`` (one row per design, units in the column names),
``alternatives.md`` (the table as Markdown) and ``alternatives.png``.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from casadi_debris.config import AXIS_NAMES
from casadi_debris.records import Record
from casadi_debris.report._common import format_figure
from casadi_debris.store import write_json_atomic
from casadi_debris.studies.alternatives import FailureTolerance, SwarmSummary

if TYPE_CHECKING:
    from matplotlib.figure import Figure

COLUMNS = (
    "problem",
    "cubesats",
    "engines",
    "swarm_mass_kg",
    "total_mass_kg",
    *(f"torque_max_{s}{a}_mNm" for a in AXIS_NAMES for s in ("+", "-")),
    "weakest_axis",
    "weakest_ratio",
    *(f"fuel_{s}{a}_g_per_mNm_h" for a in AXIS_NAMES for s in ("+", "-")),
    "single_failure_worst_ratio",
    "single_failure_worst_cubesats",
    "single_failures_above_disturbance",
    "double_failure_worst_ratio",
    "double_failure_worst_cubesats",
    "double_failures_above_disturbance",
)


@dataclass(frozen=True)
class AlternativesSummary(Record):
    """The designs compared, the failure sets tried (``max_failed``) and the wall time [s]."""

    designs: list[SwarmSummary]
    max_failed: int
    wall_time_s: float
    out_dir: str | None = None


def design_row(design: SwarmSummary) -> list[object]:
    """One design as the CSV row of :data:`COLUMNS`."""
    torque = design.torque_max_zero_force_mNm
    fuel = design.fuel_per_torque_time_g_per_mNm_h
    return [
        design.problem,
        design.cubesats,
        design.engines,
        design.swarm_mass_kg,
        design.total_mass_kg,
        *(torque[f"{s}{a}"] for a in AXIS_NAMES for s in ("+", "-")),
        design.weakest_axis,
        design.weakest_ratio,
        *(fuel[f"{s}{a}"] for a in AXIS_NAMES for s in ("+", "-")),
        *_failure_cells(design.single_failure),
        *_failure_cells(design.double_failure),
    ]


def _failure_cells(tolerance: FailureTolerance | None) -> list[object]:
    """Worst ratio, its CubeSats (1-based, ``3+17``), sets above the disturbance (``n/m``)."""
    if tolerance is None:
        return ["", "", ""]
    ids = "+".join(str(k) for k in tolerance.failed)
    return [tolerance.worst_ratio, ids, f"{tolerance.sets_above_disturbance}/{tolerance.sets}"]


def _failure_text(tolerance: FailureTolerance | None) -> str:
    if tolerance is None:
        return "—"
    ids = "+".join(str(k) for k in tolerance.failed)
    kept = f"{tolerance.sets_above_disturbance}/{tolerance.sets}"
    return f"{format_figure(tolerance.worst_ratio)} ({ids}); {kept} above"


def alternatives_markdown(designs: list[SwarmSummary]) -> str:
    """The comparison as a Markdown table (authority in mNm, weaker sign per axis)."""
    lines = [
        "| design | CubeSats / engines | swarm mass [kg] "
        "| authority x / y / z [mNm] | weakest axis / disturbance "
        "| fuel per torque·time x / y / z [g/(mN·m·h)] "
        "| worst single failure | worst double failure |",
        "| --- | ---: | ---: | ---: | ---: | ---: | --- | --- |",
    ]
    for d in designs:
        torque = d.torque_max_zero_force_mNm
        fuel = d.fuel_per_torque_time_g_per_mNm_h
        weaker = " / ".join(
            format_figure(min(torque[f"+{a}"], torque[f"-{a}"])) for a in AXIS_NAMES
        )
        costlier = " / ".join(format_figure(max(fuel[f"+{a}"], fuel[f"-{a}"])) for a in AXIS_NAMES)
        lines.append(
            f"| `{d.problem}` | {d.cubesats} / {d.engines} | {format_figure(d.swarm_mass_kg)} "
            f"| {weaker} | {format_figure(d.weakest_ratio)} ({d.weakest_axis}) | {costlier} "
            f"| {_failure_text(d.single_failure)} | {_failure_text(d.double_failure)} |"
        )
    return "\n".join(lines) + "\n"


def write_alternatives(folder: Path, report: AlternativesSummary, *, plots: bool = True) -> None:
    """``summary.json``, ``alternatives.csv``, ``alternatives.md`` and, with ``plots``,
    ``alternatives.png`` (and its PDF)."""
    write_json_atomic(folder / "summary.json", report)
    with (folder / "alternatives.csv").open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(COLUMNS)
        writer.writerows(design_row(d) for d in report.designs)
    (folder / "alternatives.md").write_text(alternatives_markdown(report.designs))
    if plots:
        from casadi_debris.plots import save_figure

        for stem, figure in alternatives_figures(report).items():
            save_figure(figure, folder / f"{stem}.png")


def alternatives_figures(report: AlternativesSummary) -> dict[str, Figure]:
    """``alternatives``: authority margin with and without failures, fuel per torque·time
    and added mass, one bar group per design."""
    from casadi_debris.plots import alternatives_figure

    return {"alternatives": alternatives_figure(list(report.designs))}
