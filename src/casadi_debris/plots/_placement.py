"""Figures of a placement study: the layout on the hub, the Pareto front."""

from __future__ import annotations

import math
from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from casadi_debris.config import Problem
from casadi_debris.geometry import array_axes
from casadi_debris.studies.placement import ParetoPoint, PlacementStudy

VIEWS = ((0, 1), (0, 2), (1, 2))
"""Projections drawn: x-y, x-z, y-z (hub-corner frame)."""
ARROW_M = 0.25


ARRAY_COLOUR = "#ef8f00"


def array_outlines_corner_m(problem: Problem) -> list[np.ndarray]:
    """Each array as the four corners of its undeformed panel at its nominal angle, in the
    hub-corner frame, shape (4, 3) each: root edge (hinge -+ half the width), then the tip
    edge a length out along the array's extent."""
    outlines = []
    for array in problem.arrays:
        extent, width, _ = (
            np.array(v, dtype=float).ravel()
            for v in array_axes(array.direction, math.radians(array.angle_deg))
        )
        half = 0.5 * array.width_m * width
        tip = array.length_m * extent
        root = np.asarray(array.hinge_corner_m, dtype=float)
        outlines.append(np.array([root - half, root + half, root + half + tip, root - half + tip]))
    return outlines


def _draw_arrays(axis: plt.Axes, problem: Problem, view: tuple[int, int]) -> None:
    """The arrays projected on the view: filled panels (a thick line when seen edge-on),
    numbered from 1 at their tips, so that a CubeSat or a plume in their way shows."""
    first, second = view
    for number, corners in enumerate(array_outlines_corner_m(problem), start=1):
        axis.fill(
            corners[:, first],
            corners[:, second],
            facecolor=ARRAY_COLOUR,
            edgecolor=ARRAY_COLOUR,
            alpha=0.35,
            linewidth=2.0,
            label="arrays (nominal angle)" if number == 1 else None,
        )
        tip = corners[2:].mean(axis=0)
        axis.annotate(
            str(number),
            (tip[first], tip[second]),
            color="0.25",
            fontsize="small",
            ha="center",
            va="center",
        )


def _in_view(face: str | None, view: tuple[int, int]) -> bool:
    """A face is drawn in the views that hold its normal (seen edge-on, thrust in plane)."""
    return face is not None and "xyz".index(face[1]) in view


def _draw_view(axis: plt.Axes, study: PlacementStudy, view: tuple[int, int]) -> None:
    first, second = view
    size = study.problem.hub.size_m
    axis.add_patch(Rectangle((0, 0), size[first], size[second], fill=False, edgecolor="0.3"))
    _draw_arrays(axis, study.problem, view)
    shown = [c for c in study.candidates.candidates if _in_view(c.face, view)]
    everywhere = np.array([c.cubesat.position_corner_m for c in shown]).reshape(-1, 3)
    axis.plot(
        everywhere[:, first],
        everywhere[:, second],
        ".",
        color="0.75",
        markersize=4,
        label="candidate mounts",
    )
    own = np.array(
        [c.position_corner_m for c in study.problem.cubesats if _in_view(c.face, view)]
    ).reshape(-1, 3)
    axis.plot(
        own[:, first],
        own[:, second],
        "s",
        markerfacecolor="none",
        markeredgecolor="0.45",
        markersize=8,
        label="input layout",
    )
    for candidate in study.chosen:
        if not _in_view(candidate.face, view):
            continue
        position = candidate.cubesat.position_corner_m
        axis.plot(position[first], position[second], "o", color="#1f5fbf", markersize=5)
        for engine in candidate.cubesat.engines:
            arrow = ARROW_M * engine.direction
            if abs(arrow[first]) + abs(arrow[second]) > 1e-9:
                axis.annotate(
                    "",
                    xy=(position[first] + arrow[first], position[second] + arrow[second]),
                    xytext=(position[first], position[second]),
                    arrowprops={"arrowstyle": "->", "color": "#c2185b", "lw": 1.0},
                )
    names = "xyz"
    axis.set_xlabel(f"{names[first]} [m]")
    axis.set_ylabel(f"{names[second]} [m]")
    axis.set_aspect("equal")
    axis.margins(0.15)


def _per_face(study: PlacementStudy) -> dict[str, int]:
    faces = [c.face for c in study.chosen]
    return {face: faces.count(face) for face in ("+x", "-x", "+y", "-y", "+z", "-z")}


def layout_figure(study: PlacementStudy) -> Figure:
    """The hub in three projections with the chosen CubeSats and their thrust.

    Each view shows the faces seen edge-on (x-y: the +-x and +-y faces, ...), so
    every face appears in two views and its thrust lies in the plane. Chosen
    CubeSats are blue dots with their engines' thrust on the body as red arrows,
    the input layout hollow squares, the other candidates grey dots, the arrays
    orange panels at their nominal angle. Hub-corner frame, metres.
    """
    figure, axes = plt.subplots(1, 3, figsize=(12, 4.6))
    for axis, view in zip(axes, VIEWS, strict=True):
        _draw_view(axis, study, view)
    axes[0].legend(loc="upper left", fontsize="x-small")
    metrics = study.metrics
    figure.suptitle(
        f"{study.problem.name}: {metrics.count} CubeSats, worst {metrics.worst_axis} at "
        f"{metrics.worst_ratio:.3g} x the disturbance (input layout "
        f"{study.input_layout.metrics.worst_ratio:.3g})\nper face (mounts behind each "
        "other along the viewing axis coincide): "
        + ", ".join(f"{face} {n}" for face, n in _per_face(study).items() if n)
    )
    return figure


def pareto_figure(points: Sequence[ParetoPoint]) -> Figure:
    """The sweep: worst authority over disturbance against count, slew time
    and weakest-direction Δv; front members filled, the input layout a star."""
    figure, axes = plt.subplots(1, 3, figsize=(13, 4.3), sharey=True)
    columns = (
        ("count", lambda p: p.metrics.count, "CubeSats"),
        ("slew", lambda p: p.metrics.slowest_slew_s, "rigid 180° slew, slowest axis [s]"),
        ("dv", lambda p: p.metrics.weakest_dv_m_s, "one-stage Δv, weakest direction [m/s]"),
    )
    counts = np.array([p.metrics.count for p in points], dtype=float)
    scale = plt.Normalize(counts.min(), counts.max())
    for axis, (_, value, label) in zip(axes, columns, strict=True):
        for point in points:
            x, y = value(point), point.metrics.worst_ratio
            colour = plt.cm.viridis(scale(point.metrics.count))
            if point.label == "input":
                axis.plot(
                    x,
                    y,
                    "*",
                    color="#c2185b",
                    markersize=16,
                    zorder=5,
                    label="input layout" + (" (on the front)" if point.on_front else ""),
                )
            elif point.on_front:
                axis.plot(x, y, "o", color=colour, markersize=7)
            else:
                axis.plot(x, y, "o", markerfacecolor="none", markeredgecolor=colour, markersize=7)
        axis.set_xlabel(label)
        axis.grid(alpha=0.3)
    axes[0].set_ylabel("worst authority / disturbance")
    axes[0].legend(loc="lower right", fontsize="small")
    colourbar = figure.colorbar(plt.cm.ScalarMappable(norm=scale, cmap="viridis"), ax=axes[-1])
    colourbar.set_label("CubeSats")
    figure.suptitle("Placement sweep: filled = Pareto front (count, authority, slew, Δv)")
    return figure
