"""Figures of slew profiles: attitude, rate, torque (and engine thrust) against time;
and of a manoeuvre's reference, segment by segment."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from casadi_debris.dynamics import (
    error_quaternion,
    euler_angles_321,
    quaternion_axis_angle,
)
from casadi_debris.guidance import SegmentPlanSummary
from casadi_debris.plots._style import AXIS_COLOURS, save_figure
from casadi_debris.slews import SlewProfile
from casadi_debris.units import MN_PER_N, MNM_PER_NM


def plot_slew(profile: SlewProfile, path: Path, thrust: bool = False) -> Path:
    """Write :func:`slew_figure` as a PNG (``path``) and a PDF beside it."""
    return save_figure(slew_figure(profile, thrust), path)


def slew_figure(profile: SlewProfile, thrust: bool = False) -> Figure:
    """Euler angles (deg), body rates (deg/s), torque (mNm) and, with ``thrust``, the
    thrust of every engine (mN), all against time (s); not written.

    A flexible slew solved with its terminal window (``settings["window_s"]``) gets
    one more panel: the torque over the last two window lengths, the window shaded.
    """
    window_s = profile.settings.get("window_s")
    main = 4 if thrust else 3
    panels = main + (1 if window_s else 0)
    figure, axes = plt.subplots(panels, 1, figsize=(8, 2.4 * panels))
    for axis in axes[1:main]:
        axis.sharex(axes[0])
    for axis in axes[: main - 1]:
        axis.tick_params(labelbottom=False)
    time = profile.time_s
    labels = {"x": r"$\Phi$ / x", "y": r"$\Theta$ / y", "z": r"$\Psi$ / z"}
    angles = np.degrees(np.unwrap(profile.euler_angles_rad, axis=0))
    rates = np.degrees(profile.rate_rad_s)
    torque = profile.torque_Nm * MNM_PER_NM
    for index, axis in enumerate("xyz"):
        colour = AXIS_COLOURS[axis]
        axes[0].plot(time, angles[:, index], color=colour, label=labels[axis])
        axes[1].plot(time, rates[:, index], color=colour)
        axes[2].step(time, torque[:, index], where="post", color=colour)
    _authority_lines(axes[2], profile)
    axes[0].set_ylabel("angle [deg]")
    axes[0].legend(loc="best", fontsize="small")
    axes[1].set_ylabel("rate [deg/s]")
    axes[2].set_ylabel("torque [mNm]")
    if thrust:
        axes[3].step(time, profile.thrust_N * MN_PER_N, where="post", linewidth=0.8)
        axes[3].set_ylabel("thrust per engine [mN]")
    axes[main - 1].set_xlabel("time [s]")
    if window_s:
        zoom = axes[-1]
        end = profile.duration_s
        shown = time >= end - 2.0 * window_s
        for index, axis in enumerate("xyz"):
            zoom.step(time[shown], torque[shown, index], where="post", color=AXIS_COLOURS[axis])
        zoom.axvspan(end - window_s, end, color="0.85", label="vibration-cancelling window")
        zoom.set_ylabel("torque [mNm]")
        zoom.set_xlabel("time [s], the end")
        zoom.legend(loc="best", fontsize="small")
    kind = f"{profile.method}{', flexible' if profile.flexible else ''}"
    kind += ", thruster level" if profile.thrusters else ""
    axes[0].set_title(
        f"{kind}: {np.degrees(profile.target.angle_rad):.0f} deg in {profile.duration_s:.1f} s, "
        f"fuel {profile.fuel_kg:.3g} kg"
        + ("" if profile.limits.limits_ok else ", NOT within the engines' limits")
    )
    for axis in axes:
        axis.grid(True, linestyle=":")
    return figure


def _authority_lines(axis: plt.Axes, profile: SlewProfile) -> None:
    """The largest pure torque about each signed axis (the check's), dashed in the axis's
    colour, when the torque comes within a factor of three of it (else off the scale)."""
    authority = profile.limits.limits_authority_Nm
    peak = float(np.max(np.abs(profile.torque_Nm), initial=0.0))
    for name, limit in authority.items():
        if 0.0 < limit <= 3.0 * peak:
            sign = 1.0 if name[0] == "+" else -1.0
            axis.axhline(
                sign * limit * MNM_PER_NM, color=AXIS_COLOURS[name[1]], linestyle="--", lw=0.7
            )


def plot_slew_comparison(profiles: Mapping[str, SlewProfile], path: Path) -> Path:
    """Write a PNG of several slews side by side: the torque about each body axis (N m)
    and the angle turned from the start (deg), against time (s).

    Parameters
    ----------
    profiles : mapping of str to SlewProfile
        Each slew by its legend label (duration added).
    path : Path
    """
    figure, axes = plt.subplots(4, 1, figsize=(8, 8), sharex=True)
    styles = ("-", "--", ":", "-.")
    for (label, profile), style in zip(profiles.items(), styles * len(profiles), strict=False):
        time = profile.time_s
        for index, axis in enumerate("xyz"):
            axes[index].step(
                time,
                profile.torque_Nm[:, index],
                where="post",
                linestyle=style,
                color=AXIS_COLOURS[axis],
            )
        turned = np.degrees(
            quaternion_axis_angle(
                error_quaternion(profile.target.q_initial_BN, profile.quaternion_BN)
            )[1]
        )
        axes[3].plot(
            time, turned, linestyle=style, color="0.2", label=f"{label}: {profile.duration_s:.4f} s"
        )
    for index, axis in enumerate("xyz"):
        axes[index].set_ylabel(f"torque {axis} [N m]")
    axes[3].set_ylabel("angle turned [deg]")
    axes[3].set_xlabel("time [s]")
    axes[3].legend(loc="best", fontsize="small")
    for axis in axes:
        axis.grid(True, linestyle=":")
    return save_figure(figure, path)


SEGMENT_SHADES = {"slew": "0.88", "hold": "white", "track": "#dcebf7", "burn": "#fbe3d0"}


def shade_segments(axis: plt.Axes, records: Sequence[SegmentPlanSummary], label: bool) -> None:
    """Shade each segment's window (slews grey, tracks blue) and, with ``label``, name
    it at the top of ``axis``."""
    for record in records:
        axis.axvspan(record.start_s, record.end_s, color=SEGMENT_SHADES[record.kind], zorder=0)
        if label:
            name = record.kind if record.segment is None else f"{record.segment}: {record.kind}"
            axis.annotate(
                name,
                ((record.start_s + record.end_s) / 2, 1.0),
                xycoords=("data", "axes fraction"),
                xytext=(0, 3),
                textcoords="offset points",
                ha="center",
                va="bottom",
                fontsize="small",
            )


def manoeuvre_figure(
    time_s: np.ndarray,
    quaternion_BN: np.ndarray,
    rate_rad_s: np.ndarray,
    records: Sequence[SegmentPlanSummary],
    title: str = "",
) -> Figure:
    """A manoeuvre's reference: 3-2-1 Euler angles Φ, Θ, Ψ (deg) and body rates (deg/s)
    against time (s), each segment shaded and numbered; not written.

    Parameters
    ----------
    time_s : ndarray, shape (n,)
    quaternion_BN : ndarray, shape (n, 4)
        Scalar first.
    rate_rad_s : ndarray, shape (n, 3)
    records : sequence of SegmentPlanSummary
    title : str
    """
    angles = np.degrees(np.unwrap(euler_angles_321(quaternion_BN), axis=0))
    panels = [("reference angle [deg]", angles), ("reference rate [deg/s]", np.degrees(rate_rad_s))]
    return segment_series_figure(time_s, panels, records, title)


def plot_segment_series(
    time_s: np.ndarray,
    panels: Sequence[tuple[str, np.ndarray]],
    records: Sequence[SegmentPlanSummary],
    path: Path,
    title: str = "",
) -> Path:
    """Write :func:`segment_series_figure` as a PNG (``path``) and a PDF beside it."""
    return save_figure(segment_series_figure(time_s, panels, records, title), path)


def segment_series_figure(
    time_s: np.ndarray,
    panels: Sequence[tuple[str, np.ndarray]],
    records: Sequence[SegmentPlanSummary],
    title: str = "",
) -> Figure:
    """x, y, z series against time (s), one panel each, segments shaded; not written.

    Parameters
    ----------
    time_s : ndarray, shape (n,)
    panels : sequence of (str, ndarray)
        Each panel's y label and values: shape (n, 3) drawn as lines, (n - 1, 3) held
        over each step (torques); the first panel's legend names Φ / x, Θ / y, Ψ / z.
    records : sequence of SegmentPlanSummary
    title : str
    """
    figure, axes = plt.subplots(len(panels), 1, figsize=(9, 2.6 * len(panels) + 0.8), sharex=True)
    for index, (axis, symbol) in enumerate(zip("xyz", ("Φ", "Θ", "Ψ"), strict=True)):
        colour = AXIS_COLOURS[axis]
        for panel, (_, values) in zip(axes, panels, strict=True):
            label = f"{symbol} / {axis}" if panel is axes[0] else None
            if len(values) == len(time_s):
                panel.plot(time_s, values[:, index], color=colour, label=label)
            else:
                panel.step(time_s[:-1], values[:, index], where="post", color=colour, label=label)
    for panel, (ylabel, _) in zip(axes, panels, strict=True):
        shade_segments(panel, records, label=panel is axes[0])
        panel.grid(True, linestyle=":")
        panel.set_xlim(time_s[0], time_s[-1])
        panel.set_ylabel(ylabel)
    axes[0].legend(loc="best", fontsize="small")
    axes[-1].set_xlabel("time [s]")
    if title:
        figure.suptitle(title)
    return figure
