"""A burn as a run folder: summary.json, series.csv and burn.png (+ PDF)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from casadi_debris.records import FLATTENED, Record
from casadi_debris.simulation.burn import BurnRun, BurnRunSummary, BurnSeries
from casadi_debris.store import write_csv, write_json_atomic
from casadi_debris.units import ARCSEC_PER_RAD, MN_PER_N

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@dataclass(frozen=True, kw_only=True)
class BurnSummary(Record):
    """A burn's figures and where they came from.

    Attributes
    ----------
    burn : BurnRunSummary
        Written into the same JSON object.
    controller_path : str
    first_stage_left_s : float or None
        The engines' first stages held this much full-thrust time at the start
        (None: full).
    out_dir : str or None
    limits_ok : bool or None
        The burn's attitude (its LVLH track) needs a torque within what the engines add
        to its thrust, gyroscopic torque included
        (:func:`~casadi_debris.guidance.burn_limits`), checked against what the engines
        have left along the run: a partly used first stage at the start, and an engine
        spent during the burn gives nothing from then on.
    limits_note : str or None
        What needs more than the engines give, with the figures ("" when within).
    worst_torque_set_ratio : float or None
        The largest gauge of that torque in the engines' set at the burn's force.
    """

    burn: BurnRunSummary = field(metadata=FLATTENED)
    controller_path: str
    first_stage_left_s: float | None = None
    out_dir: str | None = None
    limits_ok: bool | None = None
    limits_note: str | None = None
    worst_torque_set_ratio: float | None = None


def write_burn(
    folder: Path, burn: BurnRun, series: BurnSeries, report: BurnSummary, *, plots: bool = True
) -> None:
    """``summary.json``, ``series.csv`` (one row per control instant) and, with ``plots``,
    ``burn.png`` (and its PDF)."""
    write_json_atomic(folder / "summary.json", report)
    result = burn.result

    def padded(values: np.ndarray) -> np.ndarray:  # per period -> per instant (last held)
        return np.append(values, values[-1])

    columns = {
        "time_s": result.time_s,
        "pointing_error_arcsec": burn.pointing_error_rad * ARCSEC_PER_RAD,
        "thrust_along_mN": padded(series.thrust_along_N) * MN_PER_N,
        "thrust_all_engines_mN": padded(result.thrust_N.sum(axis=1)) * MN_PER_N,
        "dv_along_m_s": series.dv_along_m_s,
        "fuel_dv_kg": series.fuel_dv_kg,
        "fuel_attitude_kg": series.fuel_attitude_kg,
    }
    write_csv(folder / "series.csv", columns)
    if plots:
        from casadi_debris.plots import save_figure

        for stem, figure in burn_figures(burn, series, report).items():
            save_figure(figure, folder / f"{stem}.png")


def burn_figures(burn: BurnRun, series: BurnSeries, report: BurnSummary) -> dict[str, Figure]:
    """``burn``: the thrust axis' pointing error, the thrust and the propellant split."""
    from casadi_debris.plots import burn_figure

    return {"burn": burn_figure(burn, series, report.burn, title=report.burn.problem)}
