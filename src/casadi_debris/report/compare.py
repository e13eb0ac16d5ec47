"""A comparison of problem variants as files: CSV, Markdown table, fuel chart, summary."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from casadi_debris.plots.simulation import plot_fuel_comparison
from casadi_debris.records import Record
from casadi_debris.report.common import write_csv, write_json_atomic


@dataclass(frozen=True)
class VariantRow(Record):
    """One variant's nominal closed-loop run, reduced to the budget figures.

    Attributes
    ----------
    variant, problem : str
    fuel_kg, fuel_worst_cubesat_kg : float
        Propellant burnt in all and by the CubeSat that burnt most.
    dv_left_m_s : float
        Δv the propellant left would give the whole body.
    stage_switches : int
    slew_duration_s : float or None
        None without a slew.
    max_error_deg, torque_saturated_s : float
    failed_cubesats : int
    """

    variant: str
    problem: str
    fuel_kg: float
    fuel_worst_cubesat_kg: float
    dv_left_m_s: float
    stage_switches: int
    slew_duration_s: float | None
    max_error_deg: float
    torque_saturated_s: float
    failed_cubesats: int


@dataclass(frozen=True)
class Comparison(Record):
    """Variants side by side, and what they were flown with.

    Attributes
    ----------
    controller_path : str
    controller_plant_sha256 : str or None
        The plant the controller was designed for.
    plant_sha256 : dict of str to str
        Each variant problem's plant.
    variants : tuple of VariantRow
    out_dir : str
    """

    controller_path: str
    controller_plant_sha256: str | None
    plant_sha256: dict[str, str]
    variants: tuple[VariantRow, ...]
    out_dir: str


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


def write_comparison(folder: Path, summary: Comparison) -> None:
    """``comparison.csv``, ``comparison.md``, ``fuel.png`` and ``summary.json`` in ``folder``."""
    rows = summary.variants
    columns = {key: np.array(column(rows, key), dtype=object) for key, _ in COLUMNS}
    write_csv(folder / "comparison.csv", columns)
    (folder / "comparison.md").write_text(comparison_markdown(rows))
    plot_fuel_comparison(
        [row.variant for row in rows],
        [row.fuel_kg for row in rows],
        [row.fuel_worst_cubesat_kg for row in rows],
        folder / "fuel.png",
    )
    write_json_atomic(folder / "summary.json", summary)


def column(rows: tuple[VariantRow, ...], key: str) -> list[Any]:
    """One figure of every row, by its JSON name."""
    return [getattr(row, key) for row in rows]


def comparison_markdown(rows: tuple[VariantRow, ...]) -> str:
    """The rows as a Markdown table, display units in the header."""
    header = "| " + " | ".join(title for _, title in COLUMNS) + " |"
    rule = "| " + " | ".join("---" for _ in COLUMNS) + " |"
    lines = [header, rule]
    for row in rows:
        cells = [_cell(getattr(row, key)) for key, _ in COLUMNS]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _cell(value: Any) -> str:
    if value is None:
        return "—"
    if isinstance(value, str | int):
        return str(value)
    return f"{value:.4g}"
