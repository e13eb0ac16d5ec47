"""The transfer figure: altitude, inclination, mass and the thrust schedule against time."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from casadi_debris.orbit import TransferPlan, keplerian_from_mee
from casadi_debris.units import DEG_PER_RAD, M_PER_KM, SECONDS_PER_DAY


def altitude_inclination(elements: np.ndarray, radius_km: float) -> tuple[np.ndarray, np.ndarray]:
    """Altitude [km] and inclination [deg] of rows of slow MEE."""
    kepler = [keplerian_from_mee(row) for row in elements]
    altitude = np.array([k["semi_major_axis_m"] / M_PER_KM - radius_km for k in kepler])
    return altitude, np.array([k["inclination_rad"] * DEG_PER_RAD for k in kepler])


def transfer_figure(
    plan: TransferPlan,
    *,
    radius_km: float,
    target: tuple[float, float],
    title: str,
) -> Figure:
    """Four panels sharing time [days]: altitude, inclination, mass, and the firing direction.

    ``target`` is the target orbit's altitude [km] and inclination [deg]. The
    guidance law is the line, the optimal control problem's nodes the
    markers; the dotted vertical line is where the swarm's own stages are spent,
    the ticks in the last panel are stage switches (and, for the propellant
    objective, the OCP's throttle on its right axis).
    """
    result, guided, optimal = plan.result, plan.guided, plan.optimal
    figure, axes = plt.subplots(4, 1, figsize=(8, 10), sharex=True)
    g_days, o_days = guided.time_s / SECONDS_PER_DAY, optimal.time_s / SECONDS_PER_DAY
    g_alt, g_inc = altitude_inclination(guided.elements, radius_km)
    o_alt, o_inc = altitude_inclination(optimal.elements, radius_km)
    panels = (
        (axes[0], g_alt, o_alt, "altitude (mean) [km]", target[0]),
        (axes[1], g_inc, o_inc, "inclination [deg]", target[1]),
        (axes[2], guided.mass_kg, optimal.mass_kg, "mass [kg]", None),
    )
    for ax, guide, best, label, goal in panels:
        ax.plot(g_days, guide, color="#1f5fbf", label="Edelbaum steering (closed loop)")
        ax.plot(o_days, best, "o", ms=3, color="#c2185b", label=f"OCP, minimum {result.objective}")
        if goal is not None:
            ax.axhline(goal, color="0.4", ls="--", lw=0.8, label="target")
        ax.set_ylabel(label)
    burn_group = np.array([plan.burns[b].group + 1 for b in guided.burn])
    real = np.array([plan.burns[b].real for b in guided.burn])
    axes[3].step(
        g_days, np.where(real, burn_group, np.nan), where="post", color="k", label="own stages"
    )
    axes[3].step(
        g_days,
        np.where(real, np.nan, burn_group),
        where="post",
        color="0.6",
        label="extra (hypothetical)",
    )
    for time_s, _, _ in plan.stage_switches:
        axes[3].plot(time_s / SECONDS_PER_DAY, 0.6, "|", color="#ef8f00", ms=8)
    if result.objective == "propellant":
        throttle = axes[3].twinx()
        throttle.step(o_days[:-1], optimal.throttle, where="post", color="#c2185b", lw=0.9)
        throttle.set_ylabel("OCP throttle", color="#c2185b")
        throttle.set_ylim(0.0, 1.05)
    axes[3].set_ylabel("firing direction")
    axes[3].set_yticks(range(1, len(plan.groups) + 1))
    axes[3].set_xlabel("time [days]")
    for ax in axes:
        if not result.swarm_suffices:
            ax.axvline(result.available_time_days, color="0.3", ls=":", lw=1.0)
        ax.grid(True, ls=":", color="0.6")
    axes[0].legend(fontsize=7)
    axes[3].legend(fontsize=7, loc="upper left")
    verdict = (
        "the swarm suffices"
        if result.swarm_suffices
        else (
            f"own stages spent at {result.available_time_days:.0f} d, "
            f"{result.shortfall_dv_m_s:.1f} m/s short"
        )
    )
    axes[0].set_title(
        f"{title}: {result.transfer_dv_m_s:.1f} m/s in {result.transfer_time_days:.0f} d "
        f"(Edelbaum {result.edelbaum_dv_m_s:.1f} m/s)\n{verdict}",
        fontsize=10,
    )
    return figure
