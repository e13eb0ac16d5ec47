"""Δv, propellant, lifetime, transfer and detumble budgets (paper, Section II.E).

Every figure comes with a one-line "how" so the table says how it was computed.

The paper counts Δv per hub face: the four CubeSats of a face push the body
along its inward normal. In general the engines are grouped by the direction
of their force (a *thrust direction*; the paper's swarm has six, four engines
each): to push the debris along a direction, the body is turned so that the
engines of that direction fire. ``one face`` in a key reads as the weakest
direction's engines.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import AXIS_NAMES, Problem
from casadi_debris.geometry import (
    Authority,
    Geometry,
    build_geometry,
    thrust_directions,
    torque_authority,
)
from casadi_debris.orbit.transfer import edelbaum_dv as edelbaum_dv

# Edelbaum's formula lives with the transfer; re-exported here, beside the other budget lines.
from casadi_debris.orbit.transfer import transfer_dv_m_s
from casadi_debris.units import SECONDS_PER_HOUR


def rocket_dv(isp_s: float, g0_m_s2: float, initial_mass_kg: float, propellant_kg: float) -> float:
    """Tsiolkovsky Δv [m/s] of burning ``propellant_kg`` out of ``initial_mass_kg``."""
    return isp_s * g0_m_s2 * math.log(initial_mass_kg / (initial_mass_kg - propellant_kg))


def problem_stage_propellant_kg(problem: Problem) -> float:
    """Propellant of one stage of the problem's first engine [kg]."""
    return problem.engines[0].stage_propellant_kg(problem.constants.standard_gravity_m_s2)


def burn_dv_m_s(problem: Problem, initial_mass_kg: float, stages: dict[int, int]) -> float:
    """Rocket-equation Δv of burning the given stages of the given engines [m/s].

    With engines of several Isp the effective Isp is the propellant-weighted
    mean (total impulse over total propellant).

    Parameters
    ----------
    problem : Problem
    initial_mass_kg : float
    stages : dict
        Engine index (0-based) -> number of its stages burnt (at most its own).
    """
    g0 = problem.constants.standard_gravity_m_s2
    engines = problem.engines
    burnt = {
        index: min(count, engines[index].stages) * engines[index].stage_propellant_kg(g0)
        for index, count in stages.items()
    }
    propellant = sum(burnt.values())
    isp_values = {engines[index].isp_s for index in burnt}
    isp = (
        isp_values.pop()
        if len(isp_values) == 1
        else sum(engines[i].isp_s * kg for i, kg in burnt.items()) / propellant
    )
    return rocket_dv(isp, g0, initial_mass_kg, propellant)


def detumble_time_s(
    inertia_kgm2: np.ndarray, rate_rad_s: np.ndarray, authority: Authority
) -> float:
    """Time to null a body rate at full torque, each axis braked on its own [s].

    The slowest axis decides: max_i I_ii |omega_i| / tau_i, with tau_i the
    authority about the axis opposite to omega_i. Gyroscopic coupling is left
    out, as in the paper.
    """
    times = []
    for axis, name in enumerate(AXIS_NAMES):
        rate = float(rate_rad_s[axis])
        brake = authority[("-" if rate > 0 else "+") + name]
        if rate != 0.0:
            times.append(inertia_kgm2[axis, axis] * abs(rate) / brake if brake > 0 else math.inf)
    return max(times, default=0.0)


@dataclass(frozen=True)
class BudgetItem:
    """One budget figure with its unit-carrying key and how it was computed."""

    key: str
    value: float
    how: str


def compute_budgets(problem: Problem, geometry: Geometry | None = None) -> list[BudgetItem]:
    """The paper's Δv and lifetime budget for a problem.

    Parameters
    ----------
    problem : Problem
    geometry : Geometry, optional
        Reused if already built.

    Returns
    -------
    list of BudgetItem
        Keys ``dv_one_stage_one_face_m_s``, ``dv_three_stages_one_face_m_s``
        (all stages), ``dv_one_stage_all_faces_m_s``, ``dv_all_stages_all_faces_m_s``,
        ``dv_cubesat_one_stage_m_s``, ``dv_transfer_m_s``, ``detumble_time_h``,
        ``detumble_time_full_rigid_h``, ``detumble_dv_m_s``, ``stage_propellant_kg``,
        ``stage_life_h``.
    """
    geometry = geometry or build_geometry(problem)
    weakest = _weakest_direction(problem, geometry)
    dv_face = burn_dv_m_s(problem, geometry.mass_kg, dict.fromkeys(weakest, 1))
    return [
        *_stage_items(problem),
        *_rocket_equation_items(problem, geometry, weakest),
        _transfer_item(problem),
        *_detumble_items(problem, geometry, dv_face),
    ]


def _weakest_direction(problem: Problem, geometry: Geometry) -> list[int]:
    """The engines of the thrust direction with the least one-stage Δv."""
    groups = [members for _, members in thrust_directions(geometry)]
    return min(groups, key=lambda g: burn_dv_m_s(problem, geometry.mass_kg, dict.fromkeys(g, 1)))


def _stage_items(problem: Problem) -> list[BudgetItem]:
    """Propellant and life of one stage (of engine 1, if the engines differ)."""
    engine = problem.engines[0]
    which = (
        ""
        if len({(e.thrust_per_stage_mN, e.stage_life_h, e.isp_s) for e in problem.engines}) == 1
        else ", engine 1"
    )
    return [
        BudgetItem(
            "stage_propellant_kg",
            problem_stage_propellant_kg(problem),
            f"thrust {engine.thrust_per_stage_mN} mN x {engine.stage_life_h:g} h"
            f" / (Isp {engine.isp_s:g} s g0){which}",
        ),
        BudgetItem("stage_life_h", engine.stage_life_h, f"problem file (stage_life_h){which}"),
    ]


def _rocket_equation_items(
    problem: Problem, geometry: Geometry, weakest: list[int]
) -> list[BudgetItem]:
    """Δv of the combined body (one direction or all, one stage or all) and of a lone CubeSat."""
    engines = range(len(geometry.engines))
    stages = max(e.stages for e in problem.engines)
    n_directions = len(thrust_directions(geometry))

    def dv(members: Iterable[int], count: int) -> float:
        return burn_dv_m_s(problem, geometry.mass_kg, dict.fromkeys(members, count))

    cubesat = problem.cubesats[0]
    return [
        BudgetItem(
            "dv_one_stage_one_face_m_s",
            dv(weakest, 1),
            f"rocket equation, {len(weakest)} engines of the weakest thrust direction x 1 stage,"
            f" {geometry.mass_kg:.1f} kg combined body",
        ),
        BudgetItem(
            "dv_three_stages_one_face_m_s",
            dv(weakest, stages),
            f"rocket equation, {len(weakest)} engines x all ({stages}) stages",
        ),
        BudgetItem(
            "dv_one_stage_all_faces_m_s",
            dv(engines, 1),
            f"rocket equation, all {len(engines)} engines x 1 stage (body turned to each of"
            f" {n_directions} thrust directions)",
        ),
        BudgetItem(
            "dv_all_stages_all_faces_m_s",
            dv(engines, stages),
            f"rocket equation, {len(engines)} engines x all stages",
        ),
        BudgetItem(
            "dv_cubesat_one_stage_m_s",
            burn_dv_m_s(problem, cubesat.mass_kg, {geometry.cubesats[0].engines[0]: 1}),
            f"rocket equation, CubeSat 1 ({cubesat.mass_kg:g} kg) alone, its first engine, 1 stage",
        ),
    ]


def _transfer_item(problem: Problem) -> BudgetItem:
    """Edelbaum Δv of the problem's orbit transfer."""
    transfer = problem.transfer
    return BudgetItem(
        "dv_transfer_m_s",
        transfer_dv_m_s(problem),
        f"Edelbaum, circular {transfer.from_altitude_km:g} km /"
        f" {transfer.from_inclination_deg:g} deg -> {transfer.to_altitude_km:g} km /"
        f" {transfer.to_inclination_deg:g} deg",
    )


def _detumble_items(
    problem: Problem, geometry: Geometry, one_face_dv_m_s: float
) -> list[BudgetItem]:
    """Detumble time (paper's inertia and full rigid one) and the Δv share it uses."""
    authority = torque_authority(geometry)
    rate = problem.detumble.initial_rate_rad_s
    detumble_s = detumble_time_s(geometry.inertia_hub_cubesats_kgm2, rate, authority)
    detumble_full_s = detumble_time_s(geometry.inertia_total_kgm2, rate, authority)
    life_s = problem.engines[0].stage_life_h * SECONDS_PER_HOUR
    return [
        BudgetItem(
            "detumble_time_h",
            detumble_s / SECONDS_PER_HOUR,
            "slowest axis of I_ii |w_i| / tau_max,i, hub + CubeSats inertia (paper's I_tot)",
        ),
        BudgetItem(
            "detumble_time_full_rigid_h",
            detumble_full_s / SECONDS_PER_HOUR,
            "same with the full rigid inertia (arrays included)",
        ),
        BudgetItem(
            "detumble_dv_m_s",
            one_face_dv_m_s * detumble_s / life_s,
            "share of the one-face stage dv the detumble firing time uses (paper's accounting)",
        ),
    ]


def budgets_as_dict(items: list[BudgetItem]) -> dict[str, float]:
    """``{key: value}`` of a budget list."""
    return {item.key: item.value for item in items}
