"""Closed-loop figures: the paper's Figs. 4 and 5 redrawn (error and torque with
the Monte-Carlo envelope shaded and the torque limits dotted)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from casadi_debris.campaigns import Envelope, Extremes
from casadi_debris.plots._style import AXIS_COLOURS, OFF_SCALE, limit_line, save_figure
from casadi_debris.simulation import ClosedLoopResult
from casadi_debris.slews import euler_angles_321
from casadi_debris.units import ARCSEC_PER_RAD, DEG_PER_RAD, MN_PER_N, MNM_PER_NM

ERROR_SCALE = {"deg": DEG_PER_RAD, "arcsec": ARCSEC_PER_RAD}
ANGLE_LABELS = ("Φ", "Θ", "Ψ")


def plot_closed_loop(
    result: ClosedLoopResult,
    path: Path,
    *,
    envelope: Envelope | None = None,
    error_unit: str = "deg",
    requirement: float | None = None,
    title: str = "",
) -> Path:
    """:func:`closed_loop_figure` written to ``path`` (PNG, and PDF beside it)."""
    figure = closed_loop_figure(
        result, envelope=envelope, error_unit=error_unit, requirement=requirement, title=title
    )
    return save_figure(figure, path)


def closed_loop_figure(
    result: ClosedLoopResult,
    *,
    envelope: Envelope | None = None,
    error_unit: str = "deg",
    requirement: float | None = None,
    title: str = "",
) -> Figure:
    """Reference, attitude error and torque against time.

    The torque panel draws the run's own torque authority about each signed axis
    (dotted, + and - apart), stepping where failures or spent stages change it.

    Parameters
    ----------
    result : ClosedLoopResult
        The nominal run (solid lines).
    envelope : Envelope, optional
        Min/max over the Monte-Carlo cases (shaded).
    error_unit : {"deg", "arcsec"}
    requirement : float, optional
        The error requirement in ``error_unit``, drawn at +- (dashed).
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
        _draw_authority(bottom, result, i, colour)
    bands = envelope.bands if envelope is not None else None
    error_peak = _peak(result.error_rad, bands.error_rad if bands is not None else None)
    if requirement is not None:
        _draw_requirement(middle, requirement, error_peak * scale, error_unit)
    torque_peak = _peak(result.torque_Nm, bands.torque_Nm if bands is not None else None)
    _fit_torque(bottom, result, torque_peak * MNM_PER_NM)
    middle.set_ylabel(f"error [{error_unit}]")
    bottom.set_ylabel("torque [mNm]")
    bottom.set_xlabel("time [s]")
    for axes in (top, middle, bottom):
        axes.grid(True, ls=":", color="0.6")
    if envelope is not None and envelope.count:
        title = f"{title}\n{_envelope_note(result, envelope, scale, error_unit)}".strip()
    if title:
        top.set_title(title)
    figure.tight_layout()
    return figure


def _peak(values: np.ndarray, bands: Extremes | None = None) -> float:
    """Largest magnitude of ``values`` and of the envelope ``bands`` (min/max), NaN skipped."""
    arrays = [np.asarray(values)]
    if bands is not None:
        arrays += [np.asarray(bands.min), np.asarray(bands.max)]
    finite = [np.abs(a[np.isfinite(a)]) for a in arrays]
    return max((float(a.max()) for a in finite if a.size), default=0.0)


def _draw_requirement(axes: Axes, requirement: float, peak: float, unit: str) -> None:
    """The requirement at ± as dashed lines when in range of the data, else a note."""
    if limit_line(
        axes, requirement, peak, f"requirement ±{requirement:g} {unit}", "error", both_signs=True
    ):
        axes.legend(loc="upper right", fontsize=8)


def _fit_torque(axes: Axes, result: ClosedLoopResult, peak_mNm: float) -> None:
    """The authority lines' legend; when the least authority is far above the torque, the
    panel keeps the torque's scale and says where the authority is."""
    authority = np.asarray(result.authority_Nm) * MNM_PER_NM
    least = float(np.min(authority)) if authority.size else 0.0
    if peak_mNm > 0.0 and least > OFF_SCALE * peak_mNm:
        axes.set_ylim(-1.15 * peak_mNm, 1.15 * peak_mNm)
        axes.text(
            0.99,
            0.96,
            f"↑ authority (dotted) off scale: at least {least:.3g} mNm, "
            f"{least / peak_mNm:.3g} × the largest torque",
            transform=axes.transAxes,
            ha="right",
            va="top",
            fontsize=8,
            bbox={"boxstyle": "round", "facecolor": "white", "edgecolor": "0.6"},
        )
        return
    axes.plot([], [], color="0.3", ls=":", lw=1.0, label="authority about +axis / -axis")
    axes.legend(loc="upper right", fontsize=8)


def _envelope_note(
    result: ClosedLoopResult, envelope: Envelope, scale: float, error_unit: str
) -> str:
    """What the shading shows, and its size when it is too thin to see."""
    note = f"shaded: envelope of {envelope.count} cases"
    if envelope.bands is None:
        return note
    error = envelope.bands.error_rad
    spread = float(np.nanmax(np.where(np.isfinite(error.max), error.max - error.min, 0.0))) * scale
    drawn = float(np.ptp(result.error_rad)) * scale
    if spread < 0.01 * drawn:
        note += f" (spread at most {spread:.2g} {error_unit}, below the line width)"
    return note


def _draw_authority(axes: Axes, result: ClosedLoopResult, axis: int, colour: str) -> None:
    """Axis ``axis``'s authority, + above and - below, held from each change to the next."""
    if not len(result.authority_time_s):
        return
    times = np.append(result.authority_time_s, result.time_s[-1])
    for column, sign in ((2 * axis, 1.0), (2 * axis + 1, -1.0)):
        values = sign * result.authority_Nm[:, column] * MNM_PER_NM
        axes.step(times, np.append(values, values[-1]), where="post", color=colour, ls=":", lw=1.0)


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


def plot_thrust(
    result: ClosedLoopResult,
    path: Path,
    groups: dict[str, list[tuple[int, str]]],
    title: str = "",
) -> Path:
    """:func:`thrust_figure` written to ``path`` (PNG, and PDF beside it)."""
    return save_figure(thrust_figure(result, groups, title), path)


def thrust_figure(
    result: ClosedLoopResult, groups: dict[str, list[tuple[int, str]]], title: str = ""
) -> Figure:
    """Thrust of every engine (mN), a panel per group of engines, and propellant per CubeSat.

    Parameters
    ----------
    result : ClosedLoopResult
    groups : dict
        Panel title (e.g. ``"+x face"``) -> (engine index, 0-based; its label, e.g.
        ``"CubeSat 3"``) for every engine drawn there. The legend, beside each panel,
        gives a colour per CubeSat and a line style per engine of a CubeSat, both
        numbered from the run's own propulsion state.
    title : str
    """
    n_panels = len(groups) + 1
    rows = (n_panels + 1) // 2
    figure, axes = plt.subplots(rows, 2, figsize=(14, 2.6 * rows), squeeze=False)
    flat = axes.ravel()
    for ax, (name, engines) in zip(flat, groups.items(), strict=False):
        _thrust_panel(ax, result, [engine for engine, _ in engines])
        ax.set_title(name, fontsize=9)
    fuel = result.fuel_per_cubesat_kg * 1e6
    bars = flat[len(groups)]
    bars.bar(np.arange(1, len(fuel) + 1), fuel, color="0.4")
    bars.set_title("propellant burnt per CubeSat", fontsize=9)
    bars.set_xlabel("CubeSat")
    bars.set_ylabel("propellant [mg]")
    for ax in flat[n_panels:]:
        ax.set_visible(False)
    for ax in flat[: len(groups)]:
        ax.set_xlabel("time [s]")
    if title:
        figure.suptitle(title)
    figure.tight_layout()
    return figure


ENGINE_STYLES = ("-", "--", ":", "-.", (0, (5, 1, 1, 1, 1, 1)), (0, (1, 3)))
"""Line style of a CubeSat's 1st, 2nd, ... engine (its colour is its CubeSat's)."""


def _thrust_panel(ax: Axes, result: ClosedLoopResult, engines: list[int]) -> None:
    """The thrust of ``engines`` (0-based), a colour per CubeSat and a line style per engine
    of it, with a legend beside the panel that names each CubeSat (failed ones marked) and,
    when a CubeSat has several engines, each style."""
    owners = result.propulsion.engine_cubesat
    cubesats = list(dict.fromkeys(int(owners[e]) for e in engines))
    several = False
    for engine in engines:
        cubesat = int(owners[engine])
        own = int(np.sum(owners[:engine] == cubesat))  # its number among its CubeSat's engines
        several = several or own > 0 or int(np.sum(owners == cubesat)) > 1
        ax.plot(
            result.time_s[:-1],
            result.thrust_N[:, engine] * MN_PER_N,
            lw=0.9,
            color=f"C{cubesats.index(cubesat) % 10}",
            ls=ENGINE_STYLES[own % len(ENGINE_STYLES)],
        )
    failed = result.propulsion.failed_cubesats
    handles = [
        Line2D([], [], color=f"C{i % 10}",
               label=f"CubeSat {c + 1}" + (" (failed)" if failed[c] else ""))
        for i, c in enumerate(cubesats)
    ]  # fmt: skip
    if several:
        most = max(int(np.sum(owners == c)) for c in cubesats)
        handles += [
            Line2D([], [], color="0.35", ls=ENGINE_STYLES[k % len(ENGINE_STYLES)],
                   label=f"engine {k + 1}")
            for k in range(min(most, len(ENGINE_STYLES)))
        ]  # fmt: skip
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_ylabel("thrust [mN]")
    ax.grid(True, ls=":", color="0.6")


def _euler_deg(quaternion: np.ndarray) -> np.ndarray:
    """3-2-1 angles [Phi, Theta, Psi] in degrees, unwrapped, shape (n, 3)."""
    return np.degrees(np.unwrap(euler_angles_321(quaternion), axis=0))


def plot_comparison(
    labels: list[str],
    panels: dict[str, list[float | None]],
    bounds: dict[str, list[float | None]],
    path: Path,
) -> Path:
    """:func:`comparison_figure` written to ``path`` (PNG, and PDF beside it)."""
    return save_figure(comparison_figure(labels, panels, bounds), path)


def comparison_figure(
    labels: list[str],
    panels: dict[str, list[float | None]],
    bounds: dict[str, list[float | None]],
) -> Figure:
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
    return figure
