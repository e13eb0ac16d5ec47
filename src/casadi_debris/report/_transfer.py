"""An orbit transfer as a run folder: summary.json, guidance.csv, ocp.csv and transfer.png."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from casadi_debris.orbit import TransferPlan, TransferSummary
from casadi_debris.plots import altitude_inclination
from casadi_debris.store import write_csv, write_json_atomic
from casadi_debris.units import DEG_PER_RAD, SECONDS_PER_DAY

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def write_transfer(
    folder: Path,
    plan: TransferPlan,
    result: TransferSummary,
    radius_km: float,
    target: tuple[float, float],
    *,
    plots: bool = True,
) -> None:
    """Write the summary, both trajectories (days, km, deg, kg; burns 1-based) and, with
    ``plots``, the figure.

    ``guidance.csv`` has one row per guidance period, ``ocp.csv`` one per OCP
    node; ``direction`` is the firing thrust direction (1-based, in the order of
    ``thrust_mN``) and ``own_stage`` is 0 for a hypothetical extra burn.
    """
    write_json_atomic(folder / "summary.json", result)
    guided, optimal = plan.guided, plan.optimal
    write_csv(
        folder / "guidance.csv",
        {
            **_orbit_columns(guided.time_s, guided.elements, guided.mass_kg, radius_km),
            "yaw_deg": guided.yaw_rad * DEG_PER_RAD,
            "direction": np.array([plan.burns[b].group + 1 for b in guided.burn]),
            "own_stage": np.array([int(plan.burns[b].real) for b in guided.burn]),
        },
    )
    # Controls hold from a node to the next: the last node repeats the last segment's.
    write_csv(
        folder / "ocp.csv",
        {
            **_orbit_columns(optimal.time_s, optimal.elements, optimal.mass_kg, radius_km),
            "yaw_deg": np.append(optimal.yaw_rad, optimal.yaw_rad[-1]) * DEG_PER_RAD,
            "throttle": np.append(optimal.throttle, optimal.throttle[-1]),
            "direction": np.array(
                [plan.burns[b].group + 1 for b in np.append(optimal.burn, optimal.burn[-1])]
            ),
        },
    )
    if plots:
        from casadi_debris.plots import save_figure

        for stem, figure in transfer_figures(plan, radius_km, target).items():
            save_figure(figure, folder / f"{stem}.png")


def transfer_figures(
    plan: TransferPlan, radius_km: float, target: tuple[float, float]
) -> dict[str, Figure]:
    """``transfer``: altitude, inclination, mass and firing direction over the days."""
    from casadi_debris.plots import transfer_figure

    title = plan.result.problem
    return {"transfer": transfer_figure(plan, radius_km=radius_km, target=target, title=title)}


def _orbit_columns(
    time_s: np.ndarray, elements: np.ndarray, mass_kg: np.ndarray, radius_km: float
) -> dict[str, np.ndarray]:
    """Time [days], mean altitude [km], inclination [deg] and mass [kg] of a trajectory."""
    altitude, inclination = altitude_inclination(elements, radius_km)
    return {
        "time_days": time_s / SECONDS_PER_DAY,
        "altitude_km": altitude,
        "inclination_deg": inclination,
        "mass_kg": mass_kg,
    }
