"""Closed-loop figures: the paper's Figs. 4 and 5 redrawn (error and torque with
the Monte-Carlo envelope shaded and the torque limits dotted)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes

from casadi_debris.plots import AXIS_COLOURS, save_figure
from casadi_debris.simulation import ClosedLoopResult, Envelope
from casadi_debris.slew import euler_angles_321
from casadi_debris.units import ARCSEC_PER_RAD, DEG_PER_RAD

ERROR_SCALE = {"deg": DEG_PER_RAD, "arcsec": ARCSEC_PER_RAD}
ANGLE_LABELS = ("Φ", "Θ", "Ψ")


def plot_closed_loop(
    result: ClosedLoopResult,
    path: Path,
    *,
    torque_limits_mNm: np.ndarray,
    envelope: Envelope | None = None,
    error_unit: str = "deg",
    requirement_arcsec: float | None = None,
    title: str = "",
) -> Path:
    """Reference, attitude error and torque against time.

    Parameters
    ----------
    result : ClosedLoopResult
        The nominal run (solid lines).
    path : Path
        PNG to write.
    torque_limits_mNm : ndarray, shape (3,)
        Torque authority per axis (dotted at +-).
    envelope : Envelope, optional
        Min/max over the Monte-Carlo cases (shaded).
    error_unit : {"deg", "arcsec"}
    requirement_arcsec : float, optional
        Pointing requirement drawn at +- (dashed).
    """
    scale = ERROR_SCALE[error_unit]
    figure, (top, middle, bottom) = plt.subplots(3, 1, figsize=(8, 9), sharex=True)
    reference = _euler_deg(result.reference_BN)
    for i, axis in enumerate("xyz"):
        top.plot(result.time_s, reference[:, i], color=AXIS_COLOURS[axis], label=ANGLE_LABELS[i])
    top.set_ylabel("reference [deg]")
    top.legend(loc="best", ncols=3)

    if envelope is not None:
        _shade_envelope(middle, bottom, envelope, scale)
    for i, axis in enumerate("xyz"):
        colour = AXIS_COLOURS[axis]
        middle.plot(result.time_s, result.error_rad[:, i] * scale, color=colour, lw=1.0)
        bottom.step(
            result.time_s[:-1], result.torque_Nm[:, i] * 1e3, where="post", color=colour, lw=1.0
        )
        for sign in (1, -1):
            bottom.axhline(sign * torque_limits_mNm[i], color=colour, ls=":", lw=1.0)
    if requirement_arcsec is not None and error_unit == "arcsec":
        for sign in (1, -1):
            middle.axhline(sign * requirement_arcsec, color="k", ls="--", lw=0.8)
    middle.set_ylabel(f"error [{error_unit}]")
    bottom.set_ylabel("torque [mNm]")
    bottom.set_xlabel("time [s]")
    for axes in (top, middle, bottom):
        axes.grid(True, ls=":", color="0.6")
    if envelope is not None and envelope.count:
        title = f"{title} (shaded: envelope of {envelope.count} cases)".strip()
    if title:
        top.set_title(title)
    return save_figure(figure, path)


def _shade_envelope(error_axes: Axes, torque_axes: Axes, envelope: Envelope, scale: float) -> None:
    """Shade every axis' band: error times ``scale``, torque in mNm."""
    if envelope.bands is None:
        return
    for extremes, axes, factor in (
        (envelope.bands.error_rad, error_axes, scale),
        (envelope.bands.torque_Nm, torque_axes, 1e3),
    ):
        for i, axis in enumerate("xyz"):
            axes.fill_between(
                envelope.bin_start_s,
                extremes.min[:, i] * factor,
                extremes.max[:, i] * factor,
                color=AXIS_COLOURS[axis],
                alpha=0.2,
                linewidth=0,
                step="post",
            )


def plot_thrust(result: ClosedLoopResult, path: Path) -> Path:
    """Thrust of every CubeSat (mN) and propellant burnt per CubeSat."""
    figure, (left, right) = plt.subplots(1, 2, figsize=(11, 4), width_ratios=(3, 1))
    left.plot(result.time_s[:-1], result.thrust_N * 1e3, lw=0.6)
    left.set_xlabel("time [s]")
    left.set_ylabel("thrust per CubeSat [mN]")
    left.grid(True, ls=":", color="0.6")
    fuel = result.fuel_per_cubesat_kg * 1e6
    right.bar(np.arange(1, len(fuel) + 1), fuel, color="0.4")
    right.set_xlabel("CubeSat")
    right.set_ylabel("propellant used [mg]")
    return save_figure(figure, path)


def _euler_deg(quaternion: np.ndarray) -> np.ndarray:
    """3-2-1 angles [Phi, Theta, Psi] in degrees, unwrapped, shape (n, 3)."""
    return np.degrees(np.unwrap(euler_angles_321(quaternion), axis=0))


def plot_comparison(
    labels: list[str],
    panels: dict[str, list[float | None]],
    bounds: dict[str, list[float | None]],
    path: Path,
) -> Path:
    """One bar chart per figure, the variants side by side.

    Parameters
    ----------
    labels : list of str
        The variants.
    panels : dict
        Panel title (with its unit) -> one value per variant (None: not there,
        e.g. no slew, or the run failed; drawn as a gap marked "—").
    bounds : dict
        Panel title -> a requirement per variant, drawn as a red tick (None: none).
    path : Path
    """
    figure, axes = plt.subplots(
        len(panels), 1, figsize=(max(5.0, 1.1 * len(labels)), 1.9 * len(panels)), sharex=True
    )
    x = np.arange(len(labels))
    for ax, (title, values) in zip(np.atleast_1d(axes), panels.items(), strict=True):
        heights = [np.nan if v is None else v for v in values]
        ax.bar(x, heights, 0.6, color="C0")
        for i, value in enumerate(values):
            if value is None:
                ax.annotate("—", (x[i], 0), ha="center", va="bottom", color="0.4")
        for i, bound in enumerate(bounds.get(title, [])):
            if bound is not None:
                ax.hlines(bound, x[i] - 0.4, x[i] + 0.4, colors="C3", label="requirement")
        ax.set_ylabel(title, fontsize=8)
        ax.grid(True, axis="y", ls=":", color="0.6")
        handles, names = ax.get_legend_handles_labels()
        if handles:
            ax.legend(handles[:1], names[:1], fontsize=7, loc="upper left")
    np.atleast_1d(axes)[-1].set_xticks(x, labels, rotation=20, ha="right")
    return save_figure(figure, path)
