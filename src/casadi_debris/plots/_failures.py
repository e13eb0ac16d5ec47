"""Figures of a failure campaign: the authority each CubeSat's loss takes, per signed axis."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from casadi_debris.config import SIGNED_AXES
from casadi_debris.plots._style import save_figure

PERCENT = 100.0
ANNOTATE_UP_TO = 40
"""CubeSats up to which every cell carries its number (more would be unreadable)."""


def plot_authority_loss(
    path: Path,
    loss: np.ndarray,
    cubesat_ids: list[int],
    title: str,
    disturbance_line: np.ndarray | None = None,
) -> Path:
    """:func:`authority_loss_figure` written to ``path`` (PNG, and PDF beside it)."""
    return save_figure(authority_loss_figure(loss, cubesat_ids, title, disturbance_line), path)


def authority_loss_figure(
    loss: np.ndarray,
    cubesat_ids: list[int],
    title: str,
    disturbance_line: np.ndarray | None = None,
) -> Figure:
    """Heat map of the authority lost per failed CubeSat (rows) and signed axis (columns).

    Parameters
    ----------
    loss : ndarray, shape (n_cubesats, 6)
        Share of the whole swarm's authority lost about each signed axis
        (``+x, -x, +y, -y, +z, -z``), 0 .. 1.
    cubesat_ids : list of int
        The failed CubeSat of each row, from 1.
    title : str
    disturbance_line : ndarray of bool, shape (n_cubesats, 6), optional
        Cells where what is left no longer exceeds the disturbance, outlined.
    """
    rows = len(cubesat_ids)
    figure, ax = plt.subplots(figsize=(6.2, 1.2 + 0.28 * rows))
    image = ax.imshow(
        loss * PERCENT,
        aspect="auto",
        cmap="magma_r",
        vmin=0.0,
        vmax=PERCENT,
        interpolation="nearest",
    )
    ax.set_xticks(range(len(SIGNED_AXES)), list(SIGNED_AXES))
    ax.set_yticks(range(rows), [str(i) for i in cubesat_ids])
    ax.set(xlabel="signed axis", ylabel="failed CubeSat", title=title)
    if rows <= ANNOTATE_UP_TO:
        for (row, column), value in np.ndenumerate(loss * PERCENT):
            colour = "white" if value > PERCENT / 2 else "black"
            ax.text(column, row, f"{value:.0f}", ha="center", va="center", fontsize=7, color=colour)
    if disturbance_line is not None:
        for row, column in np.argwhere(disturbance_line):
            ax.add_patch(
                plt.Rectangle(
                    (column - 0.5, row - 0.5), 1, 1, fill=False, edgecolor="#1f5fbf", linewidth=2
                )
            )
    figure.colorbar(image, ax=ax, label="authority lost [%]")
    return figure
