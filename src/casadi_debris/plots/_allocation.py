"""The figure of one allocation: every engine's thrust against its limit."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from casadi_debris.plots._style import AXIS_COLOURS


def allocation_figure(
    thrust_mN: Sequence[float],
    limit_mN: Sequence[float],
    engine_cubesat: Sequence[int],
    torque_mNm: tuple[Sequence[float], Sequence[float]],
    title: str = "",
) -> Figure:
    """Thrust of every engine (bars) against its limit (outlines), and the torque asked
    for against the torque made, per body axis.

    Parameters
    ----------
    thrust_mN, limit_mN : sequence of float
        Per engine, in the problem's order [mN]; a limit of 0 is an engine out.
    engine_cubesat : sequence of int
        Each engine's CubeSat id (from 1): a CubeSat's engines are banded together.
    torque_mNm : (sequence of 3 floats, sequence of 3 floats)
        The torque demand and the torque achieved [mN m].
    title : str
    """
    figure, (bars, torque) = plt.subplots(
        1, 2, figsize=(13, 3.8), gridspec_kw={"width_ratios": [4, 1]}
    )
    engines = np.arange(1, len(thrust_mN) + 1)
    bars.bar(engines, limit_mN, color="none", edgecolor="0.6", label="limit")
    bars.bar(engines, thrust_mN, color="#1f5fbf", label="thrust")
    out = [e for e, limit in zip(engines, limit_mN, strict=True) if limit == 0]
    bars.plot(out, np.zeros(len(out)), "x", color="k", label="engine out" if out else None)
    if len(set(engine_cubesat)) < len(engine_cubesat):
        # CubeSats with several engines: every other CubeSat's engines on a grey band.
        for cubesat in sorted(set(engine_cubesat))[1::2]:
            own = engines[np.asarray(engine_cubesat) == cubesat]
            bars.axvspan(own.min() - 0.5, own.max() + 0.5, color="0.92", zorder=0)
        bars.set_xlabel("engine (grey bands: every other CubeSat)")
    else:
        bars.set_xlabel("engine (one per CubeSat)")
    step = max(1, len(engines) // 24)
    bars.set_xticks(engines[::step])
    bars.set_xlim(0.5, len(engines) + 0.5)
    bars.set_ylabel("thrust [mN]")
    bars.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    demand, achieved = (np.asarray(values, dtype=float) for values in torque_mNm)
    axes = np.arange(3)
    colours = [AXIS_COLOURS[a] for a in "xyz"]
    torque.bar(axes - 0.2, demand, width=0.4, color="none", edgecolor=colours, label="demand")
    torque.bar(axes + 0.2, achieved, width=0.4, color=colours, label="achieved")
    torque.axhline(0.0, color="k", lw=0.6)
    torque.set_xticks(axes, ["x", "y", "z"])
    torque.set(ylabel="torque [mN m]")
    torque.legend(fontsize=8)
    if title:
        figure.suptitle(title)
    figure.tight_layout()
    return figure
