"""The deorbit figures: altitude and perigee over time per solar case; lifetime against Δv."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from casadi_debris.orbit import CaseTrajectory
from casadi_debris.units import M_PER_KM, SECONDS_PER_YEAR

SOLAR_COLOURS = {"low": "#1f5fbf", "mean": "#2e7d32", "high": "#c2185b"}
SAMPLES = 400


def decay_figure(
    trajectories: Sequence[CaseTrajectory], *, title: str, limit_years: float
) -> Figure:
    """Apogee and perigee altitude (band) over the years, each solar case; burn ends marked.

    Parameters
    ----------
    trajectories : sequence of CaseTrajectory
    title : str
    limit_years : float
        Drawn as a vertical line.
    """
    figure, axes = plt.subplots(figsize=(8, 4.8))
    for item in trajectories:
        history = item.history
        years = history.time_s / SECONDS_PER_YEAR
        grid = np.linspace(0.0, years[-1], SAMPLES)
        perigee = np.interp(grid, years, history.perigee_altitude_m) / M_PER_KM
        apogee = np.interp(grid, years, history.apogee_altitude_m) / M_PER_KM
        colour = SOLAR_COLOURS.get(item.solar, "0.3")
        axes.fill_between(grid, perigee, apogee, color=colour, alpha=0.25, lw=0)
        axes.plot(grid, perigee, color=colour, label=f"{item.solar}: perigee (band to apogee)")
        end = history.burn_end_s / SECONDS_PER_YEAR
        if end > 0:
            axes.axvline(end, color=colour, ls=":", lw=0.9)
    axes.axvline(limit_years, color="k", ls="--", lw=1.0, label=f"{limit_years:g}-year limit")
    axes.set_xlabel("years from the start of the burn (dotted: burn ends)")
    axes.set_ylabel("altitude [km]")
    axes.set_title(f"{title}: deorbit plan per solar activity")
    axes.grid(True, ls=":", color="0.6")
    axes.legend(fontsize=8)
    return figure


def lifetime_curve_figure(
    trajectories: Sequence[CaseTrajectory],
    *,
    title: str,
    limit_years: float,
    capacity_dv_m_s: float,
) -> Figure:
    """Re-entry time against the burn's Δv per solar case, the limit and the swarm's Δv.

    Parameters
    ----------
    trajectories : sequence of CaseTrajectory
    title : str
    limit_years, capacity_dv_m_s : float
    """
    figure, axes = plt.subplots(figsize=(8, 4.8))
    for item in trajectories:
        years = np.where(np.isfinite(item.reentry_years), item.reentry_years, np.nan)
        axes.semilogy(
            item.dv_m_s,
            years,
            "o-",
            ms=3,
            color=SOLAR_COLOURS.get(item.solar, "0.3"),
            label=item.solar,
        )
    axes.axhline(limit_years, color="k", ls="--", lw=1.0, label=f"{limit_years:g} years")
    axes.axvline(capacity_dv_m_s, color="0.4", ls="-.", lw=1.0, label="swarm's Δv")
    axes.set_xlabel("deorbit Δv [m/s]")
    axes.set_ylabel("re-entry after the burn's start [years]")
    axes.set_title(f"{title}: lifetime against Δv (each case's strategy)")
    axes.grid(True, which="both", ls=":", color="0.6")
    axes.legend(fontsize=8)
    return figure
