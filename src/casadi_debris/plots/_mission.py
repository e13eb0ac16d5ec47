"""The mission's figures: the timeline, the propellant per CubeSat and stage, and the
altitude and perigee of every solar case from the start of the transfer."""

from __future__ import annotations

import math
from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from casadi_debris.orbit import CaseTrajectory
from casadi_debris.plots._deorbit import SOLAR_COLOURS
from casadi_debris.studies.mission import MissionSummary
from casadi_debris.units import DAYS_PER_YEAR, M_PER_KM, SECONDS_PER_DAY

PHASE_COLOURS = {"transfer": "#1f5fbf", "detumble": "#ef8f00", "deorbit burn": "#c2185b",
                 "decay": "0.6"}  # fmt: skip
BEYOND_HORIZON_DAYS = 200 * DAYS_PER_YEAR
SAMPLES = 600


def mission_figure(summary: MissionSummary) -> Figure:
    """Top: each phase as a bar over time (days, log scale: hours to years), the
    five-year limit from the burn's start. Bottom: propellant of each CubeSat's stages
    (stage 1, 2, ... left to right), stacked by phase, inside what each stage carries."""
    figure, (timeline, fuel) = plt.subplots(
        2, 1, figsize=(11, 7.5), gridspec_kw={"height_ratios": [1, 1.3]}
    )
    _timeline(timeline, summary)
    _stages(fuel, summary)
    return figure


BAR_HEIGHT = 0.45
LEFT_DAYS = 1e-2
"""The timeline's left edge: a quarter of a minute, below any phase's start but the first."""


def _timeline(axes: plt.Axes, summary: MissionSummary) -> None:
    """Each phase a bar (log days) with its note and duration in the gap below it: from the
    bar's start, or ending at the bar's end when it starts in the right part of the axis,
    so that no label runs over another bar or out of the axes."""
    phases = summary.phases
    spans = []
    for phase in phases:
        start = max(phase.start_days, LEFT_DAYS)
        length = phase.duration_days if phase.duration_days is not None else BEYOND_HORIZON_DAYS
        spans.append((start, start + length))
    right = 3.0 * max(end for _, end in spans)
    axes.set_xscale("log")
    axes.set_xlim(LEFT_DAYS, right)
    for row, (phase, (start, end)) in enumerate(zip(phases, spans, strict=True)):
        colour = PHASE_COLOURS.get(phase.name, "0.4")
        axes.barh(row, end - start, left=start, height=BAR_HEIGHT, color=colour)
        label = f"{phase.note}: {_duration(phase.duration_days)}"
        fraction = math.log(start / LEFT_DAYS) / math.log(right / LEFT_DAYS)
        at, align = (start, "left") if fraction < 0.55 else (end, "right")
        axes.text(
            at, row + BAR_HEIGHT / 2 + 0.04, label, fontsize=7, va="top", ha=align,
            bbox={"facecolor": "white", "edgecolor": "none", "pad": 0.5, "alpha": 0.85},
        )  # fmt: skip
    burn = next(p for p in phases if p.name == "deorbit burn")
    limit = burn.start_days + summary.limit_years * DAYS_PER_YEAR
    axes.axvline(
        limit, color="k", ls="--", lw=1.0,
        label=f"{summary.limit_years:g} years after the burn starts",
    )  # fmt: skip
    axes.set_yticks(range(len(phases)), [p.name for p in phases])
    axes.set_ylim(len(phases) - 0.35, -0.6)  # inverted: the first phase on top
    axes.set_xlabel("days from the start of the transfer")
    axes.legend(fontsize=7, loc="upper right")
    axes.set_title(f"{summary.problem}: {verdict(summary)}")


def _duration(days: float | None) -> str:
    """A phase's length in the unit that reads best (hours, days or years)."""
    if days is None:
        return "beyond the horizon"
    if days < 1.0:
        return f"{24.0 * days:.3g} h"
    if days < 2.0 * DAYS_PER_YEAR:
        return f"{days:.3g} days"
    return f"{days / DAYS_PER_YEAR:.3g} years"


def verdict(summary: MissionSummary) -> str:
    """One line: meets the rule, or under which solar cases it does not."""
    late = [c for c, y in summary.reentry_years.items() if y is None or y > summary.limit_years]
    if not late:
        return "meets the five-year rule under every solar case"
    return f"misses the five-year rule under {', '.join(late)} solar activity"


def _stages(axes: plt.Axes, summary: MissionSummary) -> None:
    capacity = np.asarray(summary.capacity_per_stage_kg) * 1e3
    n_cubesats, n_stages = capacity.shape
    width = 0.8 / n_stages
    x = (
        np.arange(1, n_cubesats + 1)[:, None]
        + (np.arange(n_stages)[None, :] - (n_stages - 1) / 2) * width
    ).ravel()
    bottom = np.zeros(x.size)
    for book in summary.books:
        grams = np.asarray(book.per_stage_kg).ravel() * 1e3
        axes.bar(x, grams, width=width * 0.9, bottom=bottom,
                 color=PHASE_COLOURS.get(book.phase, "0.4"), label=book.phase)  # fmt: skip
        bottom += grams
    axes.bar(x, capacity.ravel(), width=width * 0.9, fill=False, edgecolor="0.3", lw=0.6,
             label="stage capacity")  # fmt: skip
    axes.set_xticks(np.arange(1, n_cubesats + 1))
    axes.tick_params(axis="x", labelsize=7)
    axes.set_xlabel(f"CubeSat (stages 1 to {n_stages} left to right)")
    axes.set_ylabel("propellant [g]")
    stranded = summary.propellant_stranded_kg * 1e3
    axes.set_title(
        f"used {summary.propellant_used_kg:.2f} of {summary.propellant_total_kg:.2f} kg; "
        f"stranded (no torque-free mix can burn it) {stranded:.0f} g",
        fontsize=9,
    )
    axes.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))


def altitude_figure(summary: MissionSummary, trajectories: Sequence[CaseTrajectory]) -> Figure:
    """Mean altitude (top) and perigee (bottom) of each solar case over the years from the
    start of the transfer: the debris' orbit until the burn starts, then the burn (dotted
    line: its end) and the decay; the limit counted from the burn's start."""
    burn = next(p for p in summary.phases if p.name == "deorbit burn")
    offset_years = burn.start_days / DAYS_PER_YEAR
    figure, (mean, perigee) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    for item in trajectories:
        history = item.history
        years = history.time_s / (DAYS_PER_YEAR * SECONDS_PER_DAY)
        grid = np.linspace(0.0, years[-1], SAMPLES)
        altitude = (history.semi_major_axis_m - history.radius_m) / M_PER_KM
        colour = SOLAR_COLOURS.get(item.solar, "0.3")
        end = offset_years + history.burn_end_s / (DAYS_PER_YEAR * SECONDS_PER_DAY)
        for axes, values in ((mean, altitude), (perigee, history.perigee_altitude_m / M_PER_KM)):
            curve = np.interp(grid, years, values)
            axes.plot(
                np.concatenate([[0.0], offset_years + grid]),
                np.concatenate([[curve[0]], curve]),
                color=colour,
                label=f"{item.solar} solar activity",
            )
            if end > offset_years:
                axes.axvline(end, color=colour, ls=":", lw=0.9)
    for axes in (mean, perigee):
        axes.axvline(offset_years + summary.limit_years, color="k", ls="--", lw=1.0,
                     label=f"{summary.limit_years:g} years after the burn starts")  # fmt: skip
        axes.grid(True, ls=":", color="0.6")
    mean.set_ylabel("mean altitude [km]")
    perigee.set_ylabel("perigee altitude [km]")
    perigee.set_xlabel("years from the start of the transfer (dotted: each case's burn ends)")
    mean.legend(fontsize=8)
    mean.set_title(f"{summary.problem}: {verdict(summary)}", fontsize=10)
    return figure
