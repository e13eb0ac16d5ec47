"""Figures. The only package that imports matplotlib (headless Agg backend).

One module per subject (``plots.slew``, ``plots.robust``, ...); this module
holds what they share.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt

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
