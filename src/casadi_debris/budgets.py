"""Δv, propellant, lifetime, transfer and detumble budgets (paper, Section II.E).

Every figure comes with a one-line "how" so the table says how it was computed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.allocation import stage_propellant_kg
from casadi_debris.config import AXIS_NAMES, Problem
from casadi_debris.geometry import Geometry, build_geometry, torque_authority
from casadi_debris.units import M_PER_KM, MN_PER_N, SECONDS_PER_HOUR


def rocket_dv(isp_s: float, g0_m_s2: float, initial_mass_kg: float, propellant_kg: float) -> float:
    """Tsiolkovsky Δv [m/s] of burning ``propellant_kg`` out of ``initial_mass_kg``."""
    return isp_s * g0_m_s2 * math.log(initial_mass_kg / (initial_mass_kg - propellant_kg))


def problem_stage_propellant_kg(problem: Problem) -> float:
    """Propellant of one iESE stage of the problem's engine: thrust x life / (Isp g0) [kg]."""
    engine = problem.engine
    return stage_propellant_kg(
        engine.thrust_per_stage_mN / MN_PER_N,
        engine.stage_life_h * SECONDS_PER_HOUR,
        engine.isp_s,
        problem.constants.standard_gravity_m_s2,
    )


def edelbaum_dv(
    mu_km3_s2: float, radius_from_km: float, radius_to_km: float, inclination_change_rad: float
) -> float:
    """Edelbaum low-thrust Δv [m/s] between circular orbits with a plane change.

    dv = sqrt(V0^2 - 2 V0 V1 cos(pi/2 di) + V1^2) (Edelbaum 1961; Kechichian 1997).
    """
    v0 = math.sqrt(mu_km3_s2 / radius_from_km)
    v1 = math.sqrt(mu_km3_s2 / radius_to_km)
    dv_km_s = math.sqrt(
        v0**2 - 2.0 * v0 * v1 * math.cos(math.pi / 2.0 * inclination_change_rad) + v1**2
    )
    return dv_km_s * M_PER_KM


def detumble_time_s(inertia_kgm2: np.ndarray, rate_rad_s: np.ndarray, authority: dict) -> float:
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
    propellant = problem_stage_propellant_kg(problem)
    dv_face = _combined_body_dv(problem, geometry, propellant, problem.cubesats.per_face)
    return [
        *_stage_items(problem, propellant),
        *_rocket_equation_items(problem, geometry, propellant),
        _transfer_item(problem),
        *_detumble_items(problem, geometry, dv_face),
    ]


def _combined_body_dv(
    problem: Problem, geometry: Geometry, propellant_kg: float, n_stages: int
) -> float:
    """Rocket-equation Δv of the combined body burning ``n_stages`` stages [m/s]."""
    return rocket_dv(
        problem.engine.isp_s,
        problem.constants.standard_gravity_m_s2,
        geometry.mass_kg,
        n_stages * propellant_kg,
    )


def _stage_items(problem: Problem, propellant_kg: float) -> list[BudgetItem]:
    """Propellant and life of one stage."""
    engine = problem.engine
    return [
        BudgetItem(
            "stage_propellant_kg",
            propellant_kg,
            f"thrust {engine.thrust_per_stage_mN} mN x {engine.stage_life_h:g} h"
            f" / (Isp {engine.isp_s:g} s g0)",
        ),
        BudgetItem("stage_life_h", engine.stage_life_h, "problem file (engine.stage_life_h)"),
    ]


def _rocket_equation_items(
    problem: Problem, geometry: Geometry, propellant_kg: float
) -> list[BudgetItem]:
    """Δv of the combined body (one face or all, one stage or all) and of a lone CubeSat."""
    engine = problem.engine
    per_face = problem.cubesats.per_face
    n_cubesats = len(geometry.cubesats)

    def dv(n_stages: int) -> float:
        return _combined_body_dv(problem, geometry, propellant_kg, n_stages)

    return [
        BudgetItem(
            "dv_one_stage_one_face_m_s",
            dv(per_face),
            f"rocket equation, {per_face} CubeSats x 1 stage,"
            f" {geometry.mass_kg:.1f} kg combined body",
        ),
        BudgetItem(
            "dv_three_stages_one_face_m_s",
            dv(per_face * engine.stages),
            f"rocket equation, {per_face} CubeSats x {engine.stages} stages",
        ),
        BudgetItem(
            "dv_one_stage_all_faces_m_s",
            dv(n_cubesats),
            f"rocket equation, all {n_cubesats} CubeSats x 1 stage (body turned face by face)",
        ),
        BudgetItem(
            "dv_all_stages_all_faces_m_s",
            dv(n_cubesats * engine.stages),
            f"rocket equation, {n_cubesats} CubeSats x {engine.stages} stages",
        ),
        BudgetItem(
            "dv_cubesat_one_stage_m_s",
            rocket_dv(
                engine.isp_s,
                problem.constants.standard_gravity_m_s2,
                problem.cubesats.mass_kg,
                propellant_kg,
            ),
            f"rocket equation, one {problem.cubesats.mass_kg:g} kg CubeSat alone, 1 stage",
        ),
    ]


def _transfer_item(problem: Problem) -> BudgetItem:
    """Edelbaum Δv of the problem's orbit transfer."""
    constants, transfer = problem.constants, problem.transfer
    return BudgetItem(
        "dv_transfer_m_s",
        edelbaum_dv(
            constants.earth_mu_km3_s2,
            constants.earth_radius_km + transfer.from_altitude_km,
            constants.earth_radius_km + transfer.to_altitude_km,
            math.radians(abs(transfer.to_inclination_deg - transfer.from_inclination_deg)),
        ),
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
    life_s = problem.engine.stage_life_h * SECONDS_PER_HOUR
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
