"""Figure of a campaign's statistics: histograms against the requirement, rank correlations."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from casadi_debris.campaigns import CampaignStatistics, Driver, FigureStatistics
from casadi_debris.plots._style import save_figure

MAX_BARS = 12
"""Quantities shown per tornado (the strongest by |rho|)."""


def plot_statistics(
    statistics: CampaignStatistics,
    figures: Mapping[str, np.ndarray],
    path: Path,
    title: str = "",
) -> Path:
    """:func:`statistics_figure` written to ``path`` (PNG, and PDF beside it).

    Returns
    -------
    Path
        ``path``.
    """
    return save_figure(statistics_figure(statistics, figures, title), path)


def statistics_figure(
    statistics: CampaignStatistics, figures: Mapping[str, np.ndarray], title: str = ""
) -> Figure:
    """Histogram and tornado of rank correlations for the requirement's figure and the fuel.

    Parameters
    ----------
    statistics : CampaignStatistics
    figures : mapping of str to ndarray
        Figure name -> value per case (NaN: none), as
        :func:`~casadi_debris.campaigns.case_figures` gives.
    title : str

    Returns
    -------
    matplotlib.figure.Figure
        Open; close it with ``matplotlib.pyplot.close``.
    """
    shown = [statistics.requirement_figure]
    shown += [f for f in ("fuel_slew_kg", "fuel_kg") if f in figures][:1]
    figure, axes = plt.subplots(len(shown), 2, figsize=(11.0, 3.4 * len(shown)), squeeze=False)
    drivers = {d.figure: d for d in statistics.drivers}
    for row, name in enumerate(shown):
        _histogram(axes[row, 0], statistics.figure(name), np.asarray(figures[name]))
        _tornado(axes[row, 1], drivers[name])
    rate = f"{statistics.passed} of {statistics.cases + statistics.failed_cases} cases pass"
    figure.suptitle(
        f"{title}\n{rate} ({100 * statistics.pass_rate:.1f} %): "
        f"{statistics.requirement_figure} ≤ {statistics.requirement:g}"
    )
    figure.tight_layout()
    return figure


def _histogram(ax: plt.Axes, stats: FigureStatistics, values: np.ndarray) -> None:
    """The cases' histogram over the data's own range, with the mean, 99th percentile and
    mean + 3σ; the requirement drawn when near that range, else said to be off scale (drawn
    far away it would squash every case into one bar)."""
    finite = values[np.isfinite(values)]
    ax.hist(finite, bins=min(40, max(5, len(finite) // 4)), color="#7a9cc6", edgecolor="white")
    lines = [
        (stats.mean, "mean", "k", "-"),
        (stats.p99, "99th percentile", "#555555", "--"),
        (stats.mean_plus_3sigma, "mean + 3σ", "#555555", ":"),
    ]
    shown = [v for v, *_ in lines if np.isfinite(v)] + finite.tolist()
    low, high = (min(shown), max(shown)) if shown else (0.0, 1.0)
    reach = high - low if high > low else max(abs(high) * 0.1, 1e-12)
    requirement = stats.requirement
    if requirement is not None and low - reach <= requirement <= high + reach:
        lines.append((requirement, f"requirement {requirement:g}", "#c0392b", "-"))
        low, high = min(low, requirement), max(high, requirement)
    elif requirement is not None:
        right = requirement > high
        extreme = f"largest case {finite.max():.3g}" if right else f"smallest {finite.min():.3g}"
        ax.text(
            0.98 if right else 0.02,
            0.97,
            f"{'→' if right else '←'} requirement {requirement:g}, off scale ({extreme})",
            transform=ax.transAxes,
            ha="right" if right else "left",
            va="top",
            fontsize=8,
            color="#c0392b",
            bbox={"boxstyle": "round", "facecolor": "white", "edgecolor": "#c0392b"},
        )
        ax.set_ylim(top=1.18 * ax.get_ylim()[1])  # room for the note above the bars
    for value, label, colour, style in lines:
        ax.axvline(value, color=colour, linestyle=style, linewidth=1.4, label=f"{label}")
    margin = 0.05 * (high - low if high > low else reach)
    ax.set_xlim(low - margin, high + margin)
    ax.ticklabel_format(axis="x", style="sci", scilimits=(-3, 4))
    ax.set(xlabel=stats.figure, ylabel="cases", title=f"{stats.figure} over {stats.cases} cases")
    ax.legend(fontsize=8, loc="center right")


def _tornado(ax: plt.Axes, driver: Driver) -> None:
    names = list(driver.quantities[:MAX_BARS])[::-1]
    rho = np.array(driver.spearman_rho[:MAX_BARS])[::-1]
    colours = ["#c0392b" if r > 0 else "#2e86c1" for r in rho]
    ax.barh(range(len(names)), rho, color=colours)
    indices = list(driver.first_order_index[:MAX_BARS])[::-1]
    for row, (r, index) in enumerate(zip(rho, indices, strict=True)):
        if index is not None:  # the variance share beside the bar, on the side away from it
            ax.text(
                -0.02 if r > 0 else 0.02,
                row,
                f"S {index:.2f}",
                fontsize=7,
                ha="right" if r > 0 else "left",
                va="center",
                color="#333333",
            )
    ax.set_yticks(range(len(names)), names, fontsize=8)
    ax.axvline(0.0, color="k", linewidth=0.8)
    ax.set_xlim(-1.0, 1.0)
    ax.set(
        xlabel="Spearman rank correlation ρ  (S: first-order variance index)",
        title=f"what drives {driver.figure} (worst: {driver.worst_case_id})",
    )
    if not names:
        text = "no rank correlation\n(fewer than 3 cases, or nothing varies)"
        ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes)
