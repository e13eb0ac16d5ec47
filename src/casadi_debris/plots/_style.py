"""What the figures share: the paper's axis colours, the DPI and style sheet, saving a
figure as PNG and PDF, and drawing a limit line that may lie off the data's scale."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
from matplotlib.axes import Axes

AXIS_COLOURS = {"x": "#c2185b", "y": "#ef8f00", "z": "#1f5fbf"}  # the paper's Φ, Θ, Ψ colours
FIGURE_DPI = 150
STYLE = Path(__file__).with_name("casadi_debris.mplstyle")
"""The one style sheet of every figure (fonts, grid, line widths, colour cycle)."""
plt.style.use(STYLE)


def save_figure(figure: plt.Figure, path: Path) -> Path:
    """Write a figure as PNG (``path``) and as PDF beside it (vector, for papers), then
    close it; returns ``path``."""
    figure.tight_layout()
    figure.savefig(path, dpi=FIGURE_DPI)
    figure.savefig(Path(path).with_suffix(".pdf"))
    plt.close(figure)
    return path


OFF_SCALE = 2.5
"""A limit line more than this many times the data's peak is noted, not drawn: drawn, it
would squash the data into a flat line."""


def limit_line(
    axes: Axes, limit: float, peak: float, label: str, what: str, *, both_signs: bool
) -> bool:
    """Draw the horizontal ``limit`` (at ± with ``both_signs``) when it is within
    :data:`OFF_SCALE` times the data's ``peak`` magnitude; else keep the data's scale and
    say in the panel where the limit is. Returns whether it was drawn.

    ``label`` names the limit (``"requirement ±0.6 deg"``), ``what`` the data
    (``"error"``), in the note ``"↑ requirement ±0.6 deg: off scale, 20 × the largest
    error"``.
    """
    if peak <= 0.0 or abs(limit) <= OFF_SCALE * peak:
        for sign in (1, -1) if both_signs else (1,):
            axes.axhline(
                sign * limit, color="k", ls="--", lw=0.8, label=label if sign > 0 else None
            )
        return True
    axes.set_ylim(-1.15 * peak if both_signs else 0.0, 1.15 * peak)
    axes.text(
        0.99,
        0.96,
        f"↑ {label}: off scale, {abs(limit) / peak:.3g} × the largest {what}",
        transform=axes.transAxes,
        ha="right",
        va="top",
        fontsize=8,
        bbox={"boxstyle": "round", "facecolor": "white", "edgecolor": "0.6"},
    )
    return False
