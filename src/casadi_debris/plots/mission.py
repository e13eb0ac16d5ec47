"""The mission figure: the timeline of phases and the propellant each CubeSat spends."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from casadi_debris.plots import save_figure
from casadi_debris.studies.mission import MissionSummary

PHASE_COLOURS = {"transfer": "#1f5fbf", "detumble": "#ef8f00", "deorbit burn": "#c2185b",
                 "decay": "0.6"}  # fmt: skip


def plot_mission(summary: MissionSummary, path: Path) -> Path:
    """Top: each phase as a bar over time (days, log scale: hours to years), the
    five-year limit from the burn's start. Bottom: propellant per CubeSat, stacked by phase,
    against what each carries."""
    figure, (timeline, fuel) = plt.subplots(2, 1, figsize=(8, 7))
    phases = summary.phases
    for row, phase in enumerate(phases):
        start = max(phase.start_days, 1e-2)
        length = phase.duration_days if phase.duration_days is not None else 200 * 365.25
        timeline.barh(row, length, left=start, color=PHASE_COLOURS.get(phase.name, "0.4"))
        label = phase.note if phase.duration_days is not None else phase.note + " (beyond horizon)"
        timeline.text(start, row + 0.38, label, fontsize=7, va="bottom")
    burn = next(p for p in phases if p.name == "deorbit burn")
    limit = burn.start_days + summary.limit_years * 365.25
    timeline.axvline(
        limit,
        color="k",
        ls="--",
        lw=1.0,
        label=f"{summary.limit_years:g} years after the burn starts",
    )
    timeline.set_xscale("log")
    timeline.set_yticks(range(len(phases)), [p.name for p in phases])
    timeline.invert_yaxis()
    timeline.set_xlabel("days from the start of the transfer")
    timeline.legend(fontsize=7, loc="lower right")
    late = [c for c, y in summary.reentry_years.items() if y is None or y > summary.limit_years]
    verdict = (
        "meets the five-year rule under every solar case"
        if not late
        else f"misses the five-year rule under {', '.join(late)} solar activity"
    )
    timeline.set_title(f"{summary.problem}: {verdict}")
    ids = np.arange(1, len(summary.propellant_per_cubesat_kg["transfer"]) + 1)
    bottom = np.zeros(len(ids))
    for name, values in summary.propellant_per_cubesat_kg.items():
        grams = np.asarray(values) * 1e3
        fuel.bar(ids, grams, bottom=bottom, color=PHASE_COLOURS.get(name, "0.4"), label=name)
        bottom += grams
    fuel.set_xlabel("CubeSat")
    fuel.set_ylabel("propellant [g]")
    fuel.legend(fontsize=7, ncols=3)
    return save_figure(figure, path)
