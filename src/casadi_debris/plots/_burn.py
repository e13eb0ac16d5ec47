"""The burn figure: thrust-axis pointing error, thrust, and the propellant split."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from casadi_debris.plots._style import limit_line
from casadi_debris.simulation.burn import BurnRun, BurnRunSummary, BurnSeries
from casadi_debris.units import ARCSEC_PER_RAD, MN_PER_N

GRAMS_PER_KG = 1e3


def burn_figure(
    burn: BurnRun, series: BurnSeries, summary: BurnRunSummary, *, title: str
) -> Figure:
    """Pointing error of the thrust axis against the requirement, the thrust along the
    axis and of every engine together, and the running propellant split, with the stage
    switches marked.

    Parameters
    ----------
    burn : BurnRun
    series : BurnSeries
    summary : BurnRunSummary
    title : str
    """
    result = burn.result
    minutes = result.time_s / 60.0
    figure, (pointing, thrust, fuel) = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    error_arcsec = burn.pointing_error_rad * ARCSEC_PER_RAD
    pointing.plot(minutes, error_arcsec, color="C0", lw=1.0)
    requirement = summary.pointing_requirement_arcsec
    finite = np.abs(error_arcsec[np.isfinite(error_arcsec)])
    peak = float(finite.max()) if finite.size else 0.0
    label = f"requirement {requirement:g} arcsec"
    limit_line(pointing, requirement, peak, label, "error", both_signs=False)
    pointing.set_ylabel("thrust-axis error [arcsec]")
    pointing.set_ylim(bottom=0.0)
    thrust.plot(minutes[:-1], series.thrust_along_N * MN_PER_N, color="C1", label="net, along axis")
    total = result.thrust_N.sum(axis=1) * MN_PER_N
    thrust.plot(minutes[:-1], total, color="C2", lw=0.8, label="every engine, summed")
    thrust.set_ylabel("thrust [mN]")
    thrust.set_ylim(bottom=0.0)
    fuel.plot(minutes, series.fuel_dv_kg * GRAMS_PER_KG, color="C3", label="Δv (force alone)")
    fuel.plot(minutes, series.fuel_attitude_kg * GRAMS_PER_KG, color="C4", label="attitude")
    fuel.set_ylabel("propellant [g]")
    fuel.set_xlabel("time [min]")
    switches = [e.time_s / 60.0 for e in summary.run.events if e.stage_switch]
    for ax in (pointing, thrust, fuel):
        for when in switches:
            ax.axvline(when, color="0.5", ls=":", lw=0.8)
        ax.grid(True, ls=":", color="0.6")
    if switches:
        pointing.plot([], [], color="0.5", ls=":", label=f"stage switches ({len(switches)})")
    for ax in (pointing, thrust, fuel):
        if ax.get_legend_handles_labels()[0]:  # an off-scale requirement has no line
            ax.legend(fontsize=7)
    pointing.set_title(
        f"{title}: {summary.direction} burn, Δv {summary.dv_along_m_s * 1e3:.3g} mm/s, "
        f"max error {np.round(summary.pointing_max_arcsec, 1)} arcsec"
    )
    return figure
