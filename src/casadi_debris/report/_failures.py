"""A failure campaign as files: summary, ranked table (CSV and Markdown), re-allocation, heat map.

Everything is drawn from the summary (the JSON of a
:class:`~casadi_debris.studies.failures.FailuresSummary`), so that
a script can redraw it from ``summary.json``:

- ``summary.json``: every case with ``failed`` (CubeSat ids from 1),
  ``failed_stage``, ``torque_max_zero_force_mNm`` (the six signed axes) and
  ``closed_loop`` (``met`` and each manoeuvre's figures);
- ``cases.csv`` and ``report.md``: the cases ranked, the worst first;
- ``reallocation.csv``: each case's mean holding thrust per CubeSat beside the whole
  swarm's;
- ``authority_loss.png``: the share of the authority each single failure takes, per
  signed axis.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from casadi_debris.config import SIGNED_AXES
from casadi_debris.plots import authority_loss_figure, save_figure
from casadi_debris.records import to_jsonable
from casadi_debris.report._common import format_figure
from casadi_debris.store import write_json_atomic
from casadi_debris.studies.failures import (
    FailureCaseSummary,
    FailuresSummary,
    RunCheckSummary,
)
from casadi_debris.units import SECONDS_PER_DAY

if TYPE_CHECKING:
    from matplotlib.figure import Figure

REPORT_ROWS = 25
"""Cases ``report.md`` lists (all are in ``cases.csv``)."""
RISES_SHOWN = 3
HEATMAP = "authority_loss.png"


def _ids(ids: tuple[int, ...]) -> str:
    return " ".join(str(i) for i in ids)


def _run_figure(runs: dict[str, RunCheckSummary], name: str) -> float | None:
    """The judged figure of a manoeuvre's worst run (None: not flown)."""
    run = runs.get(name)
    return None if run is None else run.error


def _met(value: bool | None) -> str:
    return "—" if value is None else ("yes" if value else "no")


def _days(seconds: float | None) -> float | None:
    return None if seconds is None else seconds / SECONDS_PER_DAY


def _rises(case: FailureCaseSummary) -> str:
    return ", ".join(
        f"{r.cubesat} (+{r.thrust_after_mN - r.thrust_before_mN:.3g} mN)"
        for r in case.reallocation[:RISES_SHOWN]
    )


def case_row(rank: int, case: FailureCaseSummary) -> dict[str, Any]:
    """One case as a table row (a CSV line), display units in the keys."""
    holding, loop = case.holding, case.closed_loop
    torque = case.torque_max_zero_force_mNm
    row = {
        "rank": rank,
        "case_id": case.case_id,
        "failed": _ids(case.failed),
        "failed_stage": _ids(case.failed_stage),
        **{f"torque_{axis}_mNm": torque[axis] for axis in SIGNED_AXES},
        "worst_axis": case.worst_axis,
        "worst_ratio": case.worst_ratio,
        "slew_max_error_deg": _run_figure(loop.nominal, "slew"),
        "pointing_max_error_arcsec": _run_figure(loop.nominal, "pointing"),
        "corners_slew_max_error_deg": _run_figure(loop.corners, "slew"),
        "corners_pointing_max_error_arcsec": _run_figure(loop.corners, "pointing"),
        "met": _met(loop.met),
        "holding_fuel_per_period_kg": None if holding is None else holding.fuel_per_period_kg,
        "holding_fuel_spread": None if holding is None else holding.fuel_spread,
        "depletion_days": _days(None if holding is None else holding.depletion_time_s),
        "thrust_rises": _rises(case),
    }
    # As the summary's JSON has them: a non-finite figure is no figure.
    return {k: to_jsonable(v) for k, v in row.items()}


COLUMN_TITLES = {
    "rank": "rank",
    "failed": "failed CubeSats",
    "failed_stage": "failed stage of",
    "torque_mNm": "authority +x / −x / +y / −y / +z / −z [mNm]",
    "worst_ratio": "least authority / disturbance",
    "slew_max_error_deg": "slew error [deg]",
    "pointing_max_error_arcsec": "pointing error [arcsec]",
    "corners": "worst corner: slew [deg] / pointing [arcsec]",
    "met": "requirements met",
    "depletion_days": "first depletion [days]",
    "thrust_rises": "thrust rises most on (CubeSat, mean holding thrust)",
}


def _markdown_cells(row: dict[str, Any]) -> list[str]:
    corners = [row["corners_slew_max_error_deg"], row["corners_pointing_max_error_arcsec"]]
    return [
        str(row["rank"]),
        row["failed"] or "—",
        row["failed_stage"] or "—",
        format_figure([row[f"torque_{axis}_mNm"] for axis in SIGNED_AXES], 3),
        f"{format_figure(row['worst_ratio'], 3)} ({row['worst_axis']})",
        format_figure(row["slew_max_error_deg"]),
        format_figure(row["pointing_max_error_arcsec"]),
        "—" if corners == [None, None] else format_figure(corners),
        row["met"],
        format_figure(row["depletion_days"]),
        row["thrust_rises"] or "—",
    ]


def pointing_window(summary: FailuresSummary) -> str:
    """What window the pointing run covered, and whether it bounds the pointing error."""
    period = summary.disturbance_period_s
    pointing = [m for m in summary.manoeuvres if m.name == "pointing"]
    if not pointing or period is None or period <= 0.0:
        return ""
    window = pointing[0].duration_s
    share = window / period
    if share >= 1.0 - 1e-9:
        periods = "one whole period" if share < 1.0 + 1e-9 else f"{share:.3g} periods"
        return (
            f"The pointing run covers {periods} of the disturbance "
            f"({period:g} s): every phase of it, each sign about each axis, so that a "
            "failure that removes the authority the disturbance asks for at any time "
            "shows in the error."
        )
    return (
        f"The pointing run covers only {share:.2g} of the disturbance's period "
        f"({window:g} of {period:g} s): the disturbance does not go through every phase, "
        "so a failure that removes the authority about one signed axis may not show; "
        "these pointing figures do not bound the error over an orbit."
    )


def failures_markdown(summary: FailuresSummary, rows: list[dict[str, Any]]) -> str:
    """``report.md``: what was run, the baseline, the worst cases, the heat map."""
    torque = summary.baseline.torque_max_zero_force_mNm
    requirements = ", ".join(f"{k} ≤ {v:g}" for k, v in summary.requirements.items())
    flown = ", ".join(f"{m.name} ({m.duration_s:g} s)" for m in summary.manoeuvres)
    lines = [
        f"# Failure campaign: {summary.problem}",
        "",
        f"{summary.case_count} cases: every set of 1 to {summary.max_failed} failed "
        f"CubeSats of {summary.cubesats}"
        + (", and stage 1 lost on each CubeSat" if summary.stages else "")
        + ". Every failure at time 0.",
        "",
        f"Whole swarm: authority {format_figure([torque[a] for a in SIGNED_AXES], 3)} mNm "
        f"(+x / −x / +y / −y / +z / −z, zero net force) against a disturbance of "
        f"{format_figure(list(summary.disturbance_mNm), 3)} mNm (x / y / z).",
        "",
    ]
    if summary.manoeuvres:
        lines += [
            f"Closed loop (nominal plant): {flown}; requirements {requirements}. "
            + pointing_window(summary)
            + " "
            f"{summary.cases_met} cases meet them, {summary.cases_not_met} do not"
            + (
                f"; the {summary.corner_sets} worst also flew {summary.corner_plants} "
                "corners of the uncertainty set."
                if summary.corner_plants
                else "."
            ),
            "",
        ]
    else:
        lines += ["No closed-loop runs (--no-closed-loop): ranked by authority alone.", ""]
    shown = rows[:REPORT_ROWS]
    lines += [
        f"## The {len(shown)} worst cases (all in cases.csv)",
        "",
        "| " + " | ".join(COLUMN_TITLES.values()) + " |",
        "| " + " | ".join("---" for _ in COLUMN_TITLES) + " |",
        *("| " + " | ".join(_markdown_cells(row)) + " |" for row in shown),
        "",
        "First depletion: the first engine to spend every stage it may use, firing the mean "
        "thrust that cancels the disturbance (least fuel, zero net force). Thrust rises: the "
        "CubeSats whose mean thrust for that holding load rises most over the whole swarm's "
        "(reallocation.csv has every CubeSat).",
        "",
        "## Authority lost by one failed CubeSat",
        "",
        f"![authority lost per CubeSat and signed axis]({HEATMAP})",
        "",
    ]
    return "\n".join(lines)


def _write_table(path: Path, rows: list[dict[str, Any]]) -> None:
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows({k: "" if v is None else v for k, v in row.items()} for row in rows)


def reallocation_rows(summary: FailuresSummary) -> list[dict[str, Any]]:
    """Each case's mean holding thrust per CubeSat beside the whole swarm's [mN]."""
    if summary.baseline.holding is None:
        return []
    before = summary.baseline.holding.thrust_per_cubesat_mN
    rows = []
    for case in summary.cases:
        if case.holding is None:
            continue
        after = case.holding.thrust_per_cubesat_mN
        rows += [
            {
                "case_id": case.case_id,
                "cubesat": index + 1,
                "thrust_before_mN": old,
                "thrust_after_mN": new,
                "change_mN": new - old,
            }
            for index, (old, new) in enumerate(zip(before, after, strict=True))
        ]
    return rows


def single_failure_loss(summary: FailuresSummary) -> tuple[list[int], np.ndarray, np.ndarray]:
    """(CubeSat ids, authority lost (n, 6), left at or below the disturbance (n, 6)) of the
    single-CubeSat cases, by CubeSat."""
    singles = sorted(
        (c for c in summary.cases if len(c.failed) == 1 and not c.failed_stage),
        key=lambda c: c.failed[0],
    )
    loss = np.array(
        [[(c.authority_loss or {}).get(a) or 0.0 for a in SIGNED_AXES] for c in singles]
    )
    weak = np.array([[_at_most_one(c.authority_ratio[a]) for a in SIGNED_AXES] for c in singles])
    return [c.failed[0] for c in singles], loss.reshape(-1, 6), weak.reshape(-1, 6)


def _at_most_one(ratio: float | None) -> bool:
    """Authority at or below the disturbance (None or NaN, as JSON gives back infinity: no
    disturbance about that axis)."""
    return ratio is not None and ratio <= 1.0


def write_failures(folder: Path, summary: FailuresSummary, *, with_plots: bool = True) -> None:
    """Every file of a failure campaign into ``folder`` (see the module), the heat map
    with ``with_plots``."""
    rows = [case_row(rank, case) for rank, case in enumerate(summary.cases, start=1)]
    _write_table(folder / "cases.csv", rows)
    moved = reallocation_rows(summary)
    if moved:
        _write_table(folder / "reallocation.csv", moved)
    if with_plots:
        for name, figure in failure_figures(summary).items():
            save_figure(figure, folder / f"{name}.png")
    (folder / "report.md").write_text(failures_markdown(summary, rows))
    write_json_atomic(folder / "summary.json", summary)


def failure_figures(summary: FailuresSummary) -> dict[str, Figure]:
    """The campaign's figures by file stem: ``authority_loss`` (the share of the authority
    each single failure takes, per signed axis), when single failures were studied."""
    ids, loss, weak = single_failure_loss(summary)
    if not ids:
        return {}
    title = f"{summary.problem}: authority lost by one failed CubeSat"
    return {HEATMAP.removesuffix(".png"): authority_loss_figure(loss, ids, title, weak)}
