"""A comparison of problem variants as files: CSV, Markdown table, fuel chart, summary."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from casadi_debris.plots.simulation import plot_fuel_comparison
from casadi_debris.report.common import write_csv, write_json_atomic

COLUMNS = (
    ("variant", "variant"),
    ("fuel_kg", "fuel [kg]"),
    ("fuel_worst_cubesat_kg", "worst CubeSat [kg]"),
    ("dv_left_m_s", "Δv left [m/s]"),
    ("stage_switches", "stage switches"),
    ("slew_duration_s", "slew [s]"),
    ("max_error_deg", "max error [deg]"),
    ("torque_saturated_s", "saturated [s]"),
)


def write_comparison(folder: Path, rows: list[dict[str, Any]], summary: dict[str, Any]) -> None:
    """``comparison.csv``, ``comparison.md``, ``fuel.png`` and ``summary.json`` in ``folder``."""
    columns = {key: np.array([row[key] for row in rows], dtype=object) for key, _ in COLUMNS}
    write_csv(folder / "comparison.csv", columns)
    (folder / "comparison.md").write_text(comparison_markdown(rows))
    plot_fuel_comparison(
        [row["variant"] for row in rows],
        [row["fuel_kg"] for row in rows],
        [row["fuel_worst_cubesat_kg"] for row in rows],
        folder / "fuel.png",
    )
    write_json_atomic(folder / "summary.json", summary)


def comparison_markdown(rows: list[dict[str, Any]]) -> str:
    """The rows as a Markdown table, display units in the header."""
    header = "| " + " | ".join(title for _, title in COLUMNS) + " |"
    rule = "| " + " | ".join("---" for _ in COLUMNS) + " |"
    lines = [header, rule]
    for row in rows:
        cells = [_cell(row[key]) for key, _ in COLUMNS]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _cell(value: Any) -> str:
    if value is None:
        return "—"
    if isinstance(value, str | int):
        return str(value)
    return f"{value:.4g}"
