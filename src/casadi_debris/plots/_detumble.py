"""The detumble figure: body rates, torque and propellant per CubeSat."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from casadi_debris.plots._style import AXIS_COLOURS
from casadi_debris.simulation.detumble import DetumbleRunResult
from casadi_debris.units import MNM_PER_NM

AXES = ("x", "y", "z")
LINE_STYLES = (":", "-.", (0, (10, 3)), "--")
BINS = 600


def detumble_figure(result: DetumbleRunResult, *, title: str, marks_h: dict[str, float]) -> Figure:
    """Body rates (log scale) against the threshold, torque, and propellant per CubeSat.

    Parameters
    ----------
    result : DetumbleRunResult
    title : str
    marks_h : dict
        Label -> a time drawn as a vertical line on the rates [h] (estimates, bounds).
    """
    summary = result.summary
    figure, (rates, torque, fuel) = plt.subplots(3, 1, figsize=(8, 9))
    # The rates precess about once a second: drawn as their envelope over bins.
    edges = np.linspace(0.0, len(result.torque_Nm), min(BINS, len(result.torque_Nm)) + 1)
    starts = edges[:-1].astype(int)
    hours = result.time_s[starts] / 3600.0
    for i, axis in enumerate(AXES):
        colour = AXIS_COLOURS[axis]
        # Floored at 1 % of the threshold so that a body at rest still has a log axis.
        largest = np.maximum(
            np.maximum.reduceat(np.abs(result.rate_rad_s[:-1, i]), starts),
            0.01 * summary.threshold_rad_s,
        )
        rates.semilogy(hours, largest, color=colour, label=f"|ω{axis}|, largest per bin")
        low = np.minimum.reduceat(result.torque_Nm[:, i], starts) * MNM_PER_NM
        high = np.maximum.reduceat(result.torque_Nm[:, i], starts) * MNM_PER_NM
        torque.fill_between(hours, low, high, color=colour, alpha=0.35, step="post", lw=0)
    rates.axhline(summary.threshold_rad_s, color="k", ls="--", lw=0.8, label="threshold")
    for (label, value), style in zip(marks_h.items(), LINE_STYLES, strict=False):
        rates.axvline(value, color="0.3", ls=style, lw=0.9, label=label)
    rates.set_ylabel("body rate [rad/s]")
    rates.legend(fontsize=7, ncols=2)
    if not np.any(result.torque_Nm):
        torque.set_ylim(-1.0, 1.0)  # no torque at all: an axis matplotlib need not guess
    torque.set_ylabel("torque [mNm], range per bin")
    torque.set_xlabel("time [h]")
    per_cubesat = np.asarray(summary.fuel_per_cubesat_kg) * 1e3
    fuel.bar(np.arange(1, len(per_cubesat) + 1), per_cubesat, color="0.4")
    fuel.set_xlabel("CubeSat")
    fuel.set_ylabel("propellant [g]")
    if not np.any(per_cubesat):
        fuel.set_ylim(0.0, 1.0)
    for ax in (rates, torque, fuel):
        ax.grid(True, ls=":", color="0.6")
    done = summary.time_to_threshold_h
    rates.set_title(f"{title}: detumbled in {done:.1f} h" if done else f"{title}: not detumbled")
    return figure
