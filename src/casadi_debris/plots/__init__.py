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


def save_figure(figure: plt.Figure, path: Path) -> Path:
    """Write a figure as PNG and close it; returns the path."""
    figure.tight_layout()
    figure.savefig(path, dpi=FIGURE_DPI)
    plt.close(figure)
    return path
