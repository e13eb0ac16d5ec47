"""Figures of the robust design: mu, the uncertainty weight, loop shapes, margins.

Each function returns its figure (nothing written; ``save_figure`` writes one)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from casadi_debris.plots._style import AXIS_COLOURS

AXES = ("x", "y", "z")


def mu_figure(omega: np.ndarray, curves: dict[str, np.ndarray], target: float = 1.0) -> Figure:
    """Robust-performance mu against frequency, one curve per controller."""
    figure, ax = plt.subplots(figsize=(7, 4))
    for label, mu in curves.items():
        ax.semilogx(omega, mu, label=f"{label} (peak {np.max(mu):.3f})")
    ax.axhline(target, color="k", linestyle="--", linewidth=1, label="robust performance bound")
    ax.set(xlabel="frequency [rad/s]", ylabel="mu upper bound", title="Robust performance")
    ax.grid(True, which="both", linestyle=":")
    ax.legend()
    return figure


def uncertainty_weight_figure(
    omega: np.ndarray, bound: np.ndarray, weight: np.ndarray, samples: int
) -> Figure:
    """|W_i| over the per-channel bound of the sampled relative errors."""
    figure, axes = plt.subplots(1, 3, figsize=(12, 3.8), sharey=True)
    for i, ax in enumerate(axes):
        colour = AXIS_COLOURS[AXES[i]]
        ax.loglog(omega, bound[:, i], color=colour, alpha=0.5, label=f"{samples} samples (cover)")
        ax.loglog(omega, weight[:, i], color="k", label="fitted W (2nd order)")
        ax.set(xlabel="frequency [rad/s]", title=f"input {AXES[i]}")
        ax.grid(True, which="both", linestyle=":")
    axes[0].set_ylabel("relative error magnitude")
    axes[0].legend()
    return figure


def loop_shapes_figure(
    omega: np.ndarray,
    sensitivity: np.ndarray,
    complementary: np.ndarray,
    sensitivity_bound: np.ndarray,
    complementary_bound: np.ndarray,
) -> Figure:
    """Singular values of S and T with the bounds the weights impose (1/|We|, 1/|W|)."""
    figure, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, values, bound, name in (
        (axes[0], sensitivity, sensitivity_bound, "S (output sensitivity)"),
        (axes[1], complementary, complementary_bound, "T_i (input complementary sensitivity)"),
    ):
        ax.loglog(omega, values, color="#1f5fbf", alpha=0.8)
        ax.loglog(omega, bound, color="k", linestyle="--", label="weight bound")
        ax.set(xlabel="frequency [rad/s]", ylabel="singular values", title=name)
        ax.grid(True, which="both", linestyle=":")
        ax.legend()
    return figure


def margins_figure(sampled: np.ndarray, nominal: np.ndarray, limits: tuple[float, float]) -> Figure:
    """Gain vs phase margin of every sampled plant and channel, with the requirements."""
    figure, axes = plt.subplots(1, 2, figsize=(11, 4))
    for i, axis in enumerate(AXES):
        colour = AXIS_COLOURS[axis]
        axes[0].scatter(
            sampled[:, i, 1], sampled[:, i, 0], s=4, color=colour, alpha=0.4, label=axis
        )
        axes[0].scatter(nominal[i, 1], nominal[i, 0], s=60, color=colour, edgecolor="k", marker="*")
        axes[1].hist(sampled[:, i, 2], bins=40, color=colour, alpha=0.5, label=axis)
    axes[0].axhline(limits[0], color="k", linestyle="--", linewidth=1)
    axes[0].axvline(limits[1], color="k", linestyle="--", linewidth=1)
    axes[0].set(
        xlabel="phase margin [deg]", ylabel="gain margin [dB]", title="Loop-at-a-time margins"
    )
    axes[1].set(xlabel="delay margin [s]", ylabel="samples", title="Delay margins")
    for ax in axes:
        ax.grid(True, linestyle=":")
        ax.legend()
    return figure
