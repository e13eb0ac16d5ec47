"""Plan the problem's orbit transfer with the swarm's staged engines: :func:`plan_transfer`
(see the package's text)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import casadi as ca

from casadi_debris.config import Problem, check_transfer_end
from casadi_debris.errors import AllocationError, ProblemFileError
from casadi_debris.geometry import build_geometry
from casadi_debris.orbit._elements import EARTH_J2, mee_circular
from casadi_debris.orbit._propulsion import ThrustSegment, swarm_thrust
from casadi_debris.orbit.transfer._averaged import averaged_dynamics, edelbaum_dv
from casadi_debris.orbit.transfer._guidance import (
    DEFAULT_PERIOD_S,
    GuidedTransfer,
    edelbaum_guidance,
)
from casadi_debris.orbit.transfer._ocp import (
    Objective,
    OptimalTransfer,
    TransferTarget,
    solve_transfer_ocp,
)
from casadi_debris.orbit.transfer._summary import TransferSummary, summarise
from casadi_debris.orbit.transfer._thrust import Burn, burn_schedule, dv_of_burns
from casadi_debris.units import M_PER_KM

# The propellant objective may take this much longer than the guidance law.
DEFAULT_TIME_SLACK = 0.1
# OCP shooting intervals in all, at most (the paper's 7 burns: 4 each); a weak
# swarm's many burns share them, so that its NLP is no larger than the paper's.
TARGET_SEGMENTS = 28
# The minimum-time OCP's last burn is redone when it ends within this share of its
# start or end (the optimum then lies in the burn before or after), at most this often.
END_SHARE = 1e-6
MAX_RESCHEDULES = 3
# Hypothetical burns stop when they would leave less than this share of the mass.
MIN_MASS_FRACTION = 0.2


@dataclass(frozen=True, eq=False)
class TransferPlan:
    """A planned transfer: the summary and the trajectories behind it.

    Attributes
    ----------
    result : TransferSummary
    guided : GuidedTransfer
        Edelbaum steering, closed loop, through the whole burn schedule.
    optimal : OptimalTransfer
    groups : tuple of ThrustSegment
        The swarm's thrust directions (:func:`~casadi_debris.orbit._propulsion.swarm_thrust`),
        strongest first; ``Burn.group`` indexes them.
    burns : list of Burn
        The schedule the guidance flew (real burns first).
    stage_switches : list of (float, int, int)
        (time [s], CubeSat, stage) when a stage ran dry, 1-based.
    """

    result: TransferSummary
    guided: GuidedTransfer
    optimal: OptimalTransfer
    groups: tuple[ThrustSegment, ...]
    burns: list[Burn]
    stage_switches: list[tuple[float, int, int]]


def plan_transfer(
    problem: Problem,
    *,
    objective: Objective = "time",
    segments_per_burn: int | None = None,
    guidance_period_s: float = DEFAULT_PERIOD_S,
    time_slack: float = DEFAULT_TIME_SLACK,
    max_intervals: int | None = TARGET_SEGMENTS,
) -> TransferPlan:
    """The problem's ``[transfer]`` (circular to circular, plane change) with its swarm.

    Parameters
    ----------
    problem : Problem
    objective : {"time", "propellant"}
        Minimum transfer time at full thrust, or minimum propellant with a
        throttle and the time at most ``(1 + time_slack)`` times the guidance's.
    segments_per_burn : int, optional
        OCP arcs per burn; default about ``TARGET_SEGMENTS`` in all (at least one
        per burn). The arcs share at most ``TARGET_SEGMENTS`` shooting intervals,
        so that a weak swarm's many burns keep the NLP small.
    guidance_period_s : float
        How often the guidance law re-plans its yaw [s].
    time_slack : float
    max_intervals : int or None
        Most OCP shooting intervals (consecutive arcs share one); None: one per arc.

    Returns
    -------
    TransferPlan

    Raises
    ------
    ProblemFileError
        The two orbits are the same, or no thrust direction can push at zero torque.
    """
    constants, transfer = problem.constants, problem.transfer
    mu = constants.earth_mu_km3_s2 * M_PER_KM**3
    radius = constants.earth_radius_km * M_PER_KM
    earth = (mu, radius, EARTH_J2)
    start_radius = radius + transfer.from_altitude_km * M_PER_KM
    target = (
        radius + transfer.to_altitude_km * M_PER_KM,
        math.radians(transfer.to_inclination_deg),
    )
    dv_edelbaum = check_transfer(problem)
    geometry = build_geometry(problem)
    try:
        groups = swarm_thrust(problem, geometry).segments
    except AllocationError as error:
        raise ProblemFileError(
            "cubesats", "no thrust direction can push at zero net torque"
        ) from error
    burns = _schedule(groups, geometry.mass_kg, 1.5 * dv_edelbaum)
    dynamics = averaged_dynamics()
    x0 = mee_circular(start_radius, math.radians(transfer.from_inclination_deg))
    guided = edelbaum_guidance(
        dynamics, x0, geometry.mass_kg, target, burns, earth, period_s=guidance_period_s
    )
    if not guided.reached:
        raise ProblemFileError(
            "transfer", "not reachable even with extra stages before the mass runs out"
        )
    used = burns[: int(guided.burn[-1]) + 1]
    time_limit = guided.time_s[-1] * (1.0 + time_slack)
    if objective == "propellant":
        used = [b for b in burns if b.start_s < time_limit]
    data = TransferTarget(
        x0=x0,
        mass_kg=geometry.mass_kg,
        radius_m=target[0],
        inclination_rad=target[1],
        earth=earth,
        burns=used,
        guess=(guided.time_s, guided.elements, guided.mass_kg, guided.yaw_rad),
    )
    arcs = (segments_per_burn, max_intervals)
    optimal = _solve_ocp(dynamics, data, burns, objective, time_limit, arcs)
    result, switches = summarise(problem, geometry, groups, burns, guided, optimal, dv_edelbaum)
    return TransferPlan(result, guided, optimal, groups, burns, switches)


def _solve_ocp(
    dynamics: ca.Function,
    data: TransferTarget,
    burns: list[Burn],
    objective: Objective,
    time_limit_s: float,
    arcs: tuple[int | None, int | None],
) -> OptimalTransfer:
    """The OCP over ``data.burns``; at minimum time, with the end moved to the burn it lies in.

    The OCP's end is free only within its last burn. When the optimum would end
    in an earlier burn (the last one shrinks to nothing) or a later one (it runs
    its whole life), the schedule loses or gains a burn and the OCP is solved
    again, at most :data:`MAX_RESCHEDULES` times. ``arcs``: arcs per burn (default
    about :data:`TARGET_SEGMENTS` in all, at least one per burn) and most intervals.
    """
    per_burn, intervals = arcs
    tries = 0
    while True:
        optimal = solve_transfer_ocp(
            dynamics,
            data,
            objective=objective,
            time_limit_s=time_limit_s,
            segments_per_burn=per_burn or max(1, round(TARGET_SEGMENTS / len(data.burns))),
            intervals=intervals,
        )
        last = data.burns[-1]
        share = (optimal.time_s[-1] - last.start_s) / last.duration_s
        count = len(data.burns)
        tries += 1
        if objective != "time" or not optimal.success or tries > MAX_RESCHEDULES:
            return optimal
        if share < END_SHARE and count > 1:
            count -= 1
        elif share > 1.0 - END_SHARE and count < len(burns):
            count += 1
        else:
            return optimal
        data = dataclasses.replace(data, burns=burns[:count])


def transfer_dv_m_s(problem: Problem) -> float:
    """Edelbaum's Δv [m/s] between the ``[transfer]`` table's circular orbits (0 for one
    orbit written twice), unchecked."""
    constants, transfer = problem.constants, problem.transfer
    return edelbaum_dv(
        constants.earth_mu_km3_s2,
        constants.earth_radius_km + transfer.from_altitude_km,
        constants.earth_radius_km + transfer.to_altitude_km,
        math.radians(abs(transfer.to_inclination_deg - transfer.from_inclination_deg)),
    )


def check_transfer(problem: Problem) -> float:
    """Edelbaum's Δv [m/s] of the problem's ``[transfer]``, refusing one with nothing to do.

    Raises
    ------
    ProblemFileError
        The transfer does not end on the debris' ``[orbit]``
        (:func:`~casadi_debris.config.check_transfer_end`), or the from and to
        orbits are the same.
    """
    check_transfer_end(problem)
    dv = transfer_dv_m_s(problem)
    if dv <= 0.0:
        raise ProblemFileError("transfer", "the from and to orbits are the same: nothing to do")
    return dv


def _schedule(groups: tuple[ThrustSegment, ...], mass_kg: float, dv_m_s: float) -> list[Burn]:
    """The real burns and enough hypothetical ones for ``dv_m_s``, while mass is left."""
    extra = 0
    while True:
        burns = burn_schedule(groups, extra)
        dv = dv_of_burns(burns, mass_kg, MIN_MASS_FRACTION)
        if len(dv) < len(burns) or dv[-1] >= dv_m_s:
            return burns[: len(dv)]
        extra += len(groups)
