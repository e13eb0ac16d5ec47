"""The design-alternatives figure: authority margin with and without failures, fuel per
torque·time and added mass, one group of bars per swarm design."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from casadi_debris.config import AXIS_NAMES
from casadi_debris.plots._style import AXIS_COLOURS
from casadi_debris.studies.alternatives import FailureTolerance, SwarmSummary

CASE_SHADES = ("0.2", "0.5", "0.8")


def alternatives_figure(designs: list[SwarmSummary]) -> Figure:
    """Three panels, one bar group per design.

    Top: the weakest signed axis' authority over the disturbance amplitude, intact and
    after the worst single and double CubeSat failure, against the line where it equals
    the disturbance. Middle: propellant per mN·m of pure torque held an hour, per axis
    (the weaker sign). Bottom: the swarm's added mass.
    """
    names = [d.problem for d in designs]
    positions = np.arange(len(designs))
    figure, (margin, fuel, mass) = plt.subplots(3, 1, figsize=(max(7, 1.6 * len(designs)), 9))
    width = 0.26
    cases = (
        ("intact", [d.weakest_ratio for d in designs]),
        ("worst single failure", [_ratio(d.single_failure) for d in designs]),
        ("worst double failure", [_ratio(d.double_failure) for d in designs]),
    )
    for k, ((label, values), shade) in enumerate(zip(cases, CASE_SHADES, strict=True)):
        bars = margin.bar(positions + (k - 1) * width, values, width, color=shade, label=label)
        margin.bar_label(bars, fmt="%.2f", fontsize=6)  # a zero is a bar one cannot see
    margin.axhline(1.0, color="C3", lw=1.0, ls="--", label="authority = disturbance")
    margin.set_ylabel("weakest axis / disturbance")
    margin.set_ylim(0.0, 1.35 * np.nanmax([v for _, values in cases for v in values]))
    margin.legend(fontsize=7, ncols=4, loc="upper center")
    for k, axis in enumerate(AXIS_NAMES):
        values = [
            max(
                d.fuel_per_torque_time_g_per_mNm_h[f"+{axis}"],
                d.fuel_per_torque_time_g_per_mNm_h[f"-{axis}"],
            )
            for d in designs
        ]
        fuel.bar(positions + (k - 1) * width, values, width, color=AXIS_COLOURS[axis], label=axis)
    fuel.set_ylabel("propellant per torque·time\n[g / (mN·m·h)]")
    fuel.legend(fontsize=7, title="about", title_fontsize=7)
    mass.bar(positions, [d.swarm_mass_kg for d in designs], 0.5, color="0.4")
    mass.set_ylabel("swarm mass [kg]")
    for ax in (margin, fuel, mass):
        ax.set_xticks(positions, names, fontsize=8)
        ax.grid(True, axis="y", ls=":", color="0.6")
    margin.set_title("Swarm designs side by side (zero net force, one stage per engine)")
    return figure


def _ratio(tolerance: FailureTolerance | None) -> float:
    """A failure case's worst ratio, NaN (no bar) when the swarm is too small for it."""
    return float("nan") if tolerance is None else tolerance.worst_ratio
