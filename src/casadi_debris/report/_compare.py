"""A comparison of problem variants as files: CSV, Markdown table, charts, summary."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from casadi_debris.plots import comparison_figure, save_figure
from casadi_debris.records import Record
from casadi_debris.report._common import format_figure
from casadi_debris.store import write_csv, write_json_atomic

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@dataclass(frozen=True, kw_only=True)
class VariantRow(Record):
    """One variant's nominal closed-loop run, reduced to the budget figures.

    Fuel is given over the whole run (whose length may differ from one variant
    to another), over the window every variant flew (``window_s`` of the
    comparison, from the start) and during the slew, so that variants are
    compared over the same time.

    Attributes
    ----------
    variant, problem : str
    error : str or None
        Why the variant's run failed (its other figures are then None).
    duration_s : float or None
        Length of the run.
    fuel_kg, fuel_window_kg, fuel_slew_kg, fuel_worst_cubesat_kg : float or None
        Propellant burnt: over the run, over the common window, during the slew
        (None without one), and by the CubeSat that burnt most over the run.
    dv_left_m_s : float or None
        Δv the propellant left would give the whole body.
    stage_switches : int or None
    slew_duration_s : float or None
        None without a slew.
    max_error_deg, max_error_arcsec : float or None
        Largest attitude error component over the run.
    requirement : str
        What the run is judged against: ``"slew_error_deg"`` for a run with a
        slew, ``"pointing_arcsec"`` for a hold (the problem's ``[requirements]``).
    required : float
        The requirement's value, in its unit.
    requirement_met : bool or None
        Whether the max error is within it (None: the run failed).
    torque_saturated_s : float or None
    failed_cubesats : int or None
    """

    variant: str
    problem: str
    error: str | None = None
    duration_s: float | None = None
    fuel_kg: float | None = None
    fuel_window_kg: float | None = None
    fuel_slew_kg: float | None = None
    fuel_worst_cubesat_kg: float | None = None
    dv_left_m_s: float | None = None
    stage_switches: int | None = None
    slew_duration_s: float | None = None
    max_error_deg: float | None = None
    max_error_arcsec: float | None = None
    requirement: str
    required: float
    requirement_met: bool | None = None
    torque_saturated_s: float | None = None
    failed_cubesats: int | None = None


@dataclass(frozen=True)
class CompareSummary(Record):
    """Variants side by side, and what they were flown with.

    Attributes
    ----------
    controller_path : str
    controller_plant_sha256 : str or None
        The plant the controller was designed for.
    plant_sha256 : dict of str to str
        Each variant problem's plant.
    window_s : float
        The time every variant flew, from the start: the shortest run.
    variants : tuple of VariantRow
    out_dir : str or None
        Where it was written (None until it is).
    """

    controller_path: str
    controller_plant_sha256: str | None
    plant_sha256: dict[str, str]
    window_s: float
    variants: tuple[VariantRow, ...]
    out_dir: str | None


COLUMNS = (
    ("variant", "variant"),
    ("duration_s", "run [s]"),
    ("fuel_kg", "fuel, run [kg]"),
    ("fuel_window_kg", "fuel, common window [kg]"),
    ("fuel_slew_kg", "fuel, slew [kg]"),
    ("fuel_worst_cubesat_kg", "worst CubeSat [kg]"),
    ("dv_left_m_s", "Δv left [m/s]"),
    ("stage_switches", "stage switches"),
    ("slew_duration_s", "slew [s]"),
    ("max_error_deg", "max error [deg]"),
    ("verdict", "requirement"),
    ("torque_saturated_s", "saturated [s]"),
)
# The charts: one panel per figure, in its display unit.
CHARTS = (
    ("fuel_window_kg", "fuel, common window [mg]", 1e6),
    ("fuel_slew_kg", "fuel during the slew [mg]", 1e6),
    ("fuel_worst_cubesat_kg", "worst CubeSat, run [mg]", 1e6),
    ("max_error_deg", "max error [deg]", 1.0),
    ("torque_saturated_s", "torque saturated [s]", 1.0),
)


def verdict(row: VariantRow) -> str:
    """The row's verdict as printed: the run's failure, or met / NOT met with the bound."""
    if row.error is not None:
        return f"run failed: {row.error}"
    if row.requirement == "slew_error_deg":
        bound = f"slew error ≤ {format_figure(row.required)} deg"
    else:
        bound = f"pointing ≤ {format_figure(row.required)} arcsec"
    return ("met: " if row.requirement_met else "NOT met: ") + bound


def cell(row: VariantRow, key: str) -> Any:
    """One figure of ``row`` by its column name (``verdict`` is computed)."""
    return verdict(row) if key == "verdict" else getattr(row, key)


def write_comparison(folder: Path, summary: CompareSummary, *, with_plots: bool = True) -> None:
    """``comparison.csv``, ``comparison.md``, ``comparison.png`` (``with_plots``) and
    ``summary.json``."""
    rows = summary.variants
    columns = {key: np.array([cell(row, key) for row in rows], dtype=object) for key, _ in COLUMNS}
    write_csv(folder / "comparison.csv", columns)
    (folder / "comparison.md").write_text(comparison_markdown(summary))
    if with_plots:
        for name, figure in comparison_figures(summary).items():
            save_figure(figure, folder / f"{name}.png")
    write_json_atomic(folder / "summary.json", summary)


def comparison_figures(summary: CompareSummary) -> dict[str, Figure]:
    """``comparison``: one bar chart per figure (fuel, error, saturation), the variants
    side by side, each slew's error bound drawn."""
    rows = summary.variants
    panels = {
        title: [None if (v := getattr(row, key)) is None else v * factor for row in rows]
        for key, title, factor in CHARTS
    }
    required = {"max error [deg]": _slew_bounds(rows)}
    return {"comparison": comparison_figure([row.variant for row in rows], panels, required)}


def _slew_bounds(rows: tuple[VariantRow, ...]) -> list[float | None]:
    """Each row's slew error bound [deg], None for a hold (judged in arcsec)."""
    return [row.required if row.requirement == "slew_error_deg" else None for row in rows]


def comparison_markdown(summary: CompareSummary) -> str:
    """The rows as a Markdown table, display units in the header."""
    header = "| " + " | ".join(title for _, title in COLUMNS) + " |"
    rule = "| " + " | ".join("---" for _ in COLUMNS) + " |"
    lines = [
        f"Fuel over the common window: the first {summary.window_s:.6g} s of every run.",
        "",
        header,
        rule,
    ]
    for row in summary.variants:
        cells = [format_figure(cell(row, key)) for key, _ in COLUMNS]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"
