"""What a layout is worth: authority over disturbance, rigid slew time, Δv per direction.

Every figure comes from the toolkit's own functions on the placed problem (the
input problem with the layout's CubeSats as an explicit list): the authority from
:func:`casadi_debris.geometry.torque_authority` (what ``casadi-debris model``
reports), the slew time from :mod:`casadi_debris.slews._maneuver`'s eigenaxis
bang-bang, the Δv from :mod:`casadi_debris.budgets`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.budgets import burn_dv_m_s
from casadi_debris.config import AXIS_NAMES, SIGNED_AXES, CubeSat, Problem
from casadi_debris.errors import SlewInfeasibleError
from casadi_debris.geometry import (
    Authority,
    Geometry,
    build_geometry,
    thrust_directions,
    torque_authority,
)
from casadi_debris.slews import eigenaxis_acceleration_limit, rigid_limit_duration
from casadi_debris.studies.failures import axis_ratios
from casadi_debris.studies.placement._data import bare_debris

DIRECTION_TOLERANCE = 1e-9


def placed_problem(
    problem: Problem, cubesats: tuple[CubeSat, ...], name: str | None = None
) -> Problem:
    """The problem with these CubeSats as its explicit list (no layout generator)."""
    return dataclasses.replace(
        problem, cubesats=cubesats, cubesat_layout=None, name=name or problem.name
    )


@dataclass(frozen=True)
class LayoutMetrics:
    """One layout's figures (SI).

    Attributes
    ----------
    count : int
        CubeSats.
    authority_Nm : dict
        Zero-net-force torque authority per signed axis (``"+x"`` ... ``"-z"``).
    ratio : dict
        Authority over the disturbance amplitude per signed axis.
    worst_axis : str
        The signed axis of the least ratio.
    slew_s : ndarray, shape (3,)
        Rigid rest-to-rest eigenaxis bang-bang time about x, y, z with the full
        rigid inertia and the zero-net-force authority box (inf without
        authority).
    dv_one_stage_m_s : dict
        Per signed thrust direction (the force the engines exert on the body),
        rocket-equation Δv of one stage of the engines pushing that way (0 when
        none does).
    added_inertia_kgm2 : ndarray, shape (3,)
        Diagonal of the full rigid inertia about the combined CoG minus the bare
        debris' about its own.
    mass_kg : float
    inertia_total_kgm2 : ndarray, shape (3, 3)
    """

    count: int
    authority_Nm: Authority
    ratio: dict[str, float]
    worst_axis: str
    slew_s: np.ndarray
    dv_one_stage_m_s: dict[str, float]
    added_inertia_kgm2: np.ndarray
    mass_kg: float
    inertia_total_kgm2: np.ndarray

    @property
    def worst_ratio(self) -> float:
        return self.ratio[self.worst_axis]

    @property
    def slowest_slew_s(self) -> float:
        """The slowest body axis's rigid slew time."""
        return float(np.max(self.slew_s))

    @property
    def weakest_dv_m_s(self) -> float:
        """The least one-stage Δv over the six signed directions."""
        return min(self.dv_one_stage_m_s.values())


def rigid_slew_times_s(geometry: Geometry, authority_Nm: Authority, angle_deg: float) -> np.ndarray:
    """Eigenaxis bang-bang time about each body axis [s], shape (3,); inf without authority."""
    upper = authority_Nm.positive_Nm
    lower = -authority_Nm.negative_Nm
    times = []
    for axis in range(3):
        try:
            alpha = eigenaxis_acceleration_limit(
                geometry.inertia_total_kgm2, np.eye(3)[axis], lower, upper
            )
        except SlewInfeasibleError:
            times.append(math.inf)
            continue
        times.append(
            rigid_limit_duration(math.radians(angle_deg), alpha) if alpha > 0 else math.inf
        )
    return np.array(times)


def direction_dv_m_s(problem: Problem, geometry: Geometry) -> dict[str, float]:
    """One-stage Δv per signed thrust direction (:func:`casadi_debris.budgets.burn_dv_m_s`)."""
    dv: dict[str, float] = dict.fromkeys(SIGNED_AXES, 0.0)
    for direction, engines in thrust_directions(geometry):
        for name in SIGNED_AXES:
            axis = AXIS_NAMES.index(name[1])
            target = np.eye(3)[axis] * (1.0 if name[0] == "+" else -1.0)
            if np.linalg.norm(direction - target) < DIRECTION_TOLERANCE:
                dv[name] = burn_dv_m_s(problem, geometry.mass_kg, dict.fromkeys(engines, 1))
    return dv


def layout_metrics(
    problem: Problem, cubesats: tuple[CubeSat, ...], slew_angle_deg: float = 180.0
) -> LayoutMetrics:
    """The figures of the problem's debris carrying these CubeSats (see the module)."""
    placed = placed_problem(problem, cubesats)
    geometry = build_geometry(placed)
    authority = torque_authority(geometry, zero_net_force=True)
    disturbance = np.abs(np.asarray(problem.disturbance.amplitude_mNm, dtype=float)) * 1e-3
    ratio = axis_ratios(authority, disturbance)
    _, bare_inertia = bare_debris(problem)
    return LayoutMetrics(
        count=len(cubesats),
        authority_Nm=authority,
        ratio=ratio,
        worst_axis=min(SIGNED_AXES, key=lambda name: ratio[name]),
        slew_s=rigid_slew_times_s(geometry, authority, slew_angle_deg),
        dv_one_stage_m_s=direction_dv_m_s(placed, geometry),
        added_inertia_kgm2=np.diag(geometry.inertia_total_kgm2) - np.diag(bare_inertia),
        mass_kg=geometry.mass_kg,
        inertia_total_kgm2=geometry.inertia_total_kgm2,
    )
