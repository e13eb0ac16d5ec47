"""The combined-body model as named ``casadi.Function``s.

Everything downstream (linearisation, simulation, slews) calls these
Functions, never the raw expressions: one model, one set of equations.

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.dynamics import build_model
>>> model = build_model(load_problem())
>>> x0 = model.initial_state()
>>> xdot = model.dynamics(x0, [0.001, 0, 0] + [0] * 6, model.nominal_parameters)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import casadi as ca
import numpy as np
import numpy.typing as npt

from casadi_debris.config import Mode, Problem
from casadi_debris.dynamics._attitude import attitude_error_vector
from casadi_debris.dynamics._flexible_body import INPUT_NAMES, FlexibleBodyEquations, StateLayout
from casadi_debris.dynamics._parameters import ParameterLayout, Parameters
from casadi_debris.errors import InputShapeError, ModelError
from casadi_debris.geometry import Geometry, build_geometry
from casadi_debris.units import NM_PER_MNM, SECONDS_PER_MINUTE


@dataclass(frozen=True, eq=False)
class Model:
    """Compiled model of the combined body.

    Attributes
    ----------
    problem : Problem
    geometry : Geometry
    layout : StateLayout
        Slices of the state vector x.
    dynamics : casadi.Function
        ``dynamics(x, u, p) -> xdot``; u = [torque (3) N m, disturbance torque
        (3) N m, force (3) N] in B; p laid out as ``parameter_layout``.
    measured_attitude : casadi.Function
        ``measured_attitude(x) -> y``: star-tracker attitude as the doubled
        vector part of q_ST (rad, ~[Phi, Theta, Psi]).
    attitude_error : casadi.Function
        ``attitude_error(q_ref, q) -> e`` (rad), short way round.
    energy : casadi.Function
        ``energy(x, p) -> E`` kinetic + modal strain energy (J).
    momenta : casadi.Function
        ``momenta(x, p) -> (p_N, h_N)`` linear (kg m/s) and angular (N m s,
        about the undeformed CoG) momentum in inertial components.
    mass_matrix : casadi.Function
        ``mass_matrix(p) -> M`` for nu = [v, omega, eta_dot].
    rigid_inertia : casadi.Function
        ``rigid_inertia(p) -> J`` (kg m^2) about the CoG.
    disturbance : casadi.Function
        ``disturbance(t) -> tau_d`` (N m): the problem's sine disturbance.
    nominal : Parameters
        The parameters at the problem's nominal values, by name.
    """

    problem: Problem
    geometry: Geometry
    layout: StateLayout
    dynamics: ca.Function
    measured_attitude: ca.Function
    attitude_error: ca.Function
    energy: ca.Function
    momenta: ca.Function
    mass_matrix: ca.Function
    rigid_inertia: ca.Function
    disturbance: ca.Function
    nominal: Parameters

    @property
    def parameter_layout(self) -> ParameterLayout:
        """Which entry of ``p`` is which."""
        return self.nominal.layout

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """Names of the entries of ``p``, in order."""
        return self.nominal.layout.names

    @property
    def nominal_parameters(self) -> np.ndarray:
        """The nominal parameter vector ``p``, shape (parameter_layout.size,)."""
        return self.nominal.to_vector()

    @property
    def input_names(self) -> tuple[str, ...]:
        return INPUT_NAMES

    def parameters(self, **values: float) -> np.ndarray:
        """Parameter vector: nominal, with the named entries replaced.

        Example: ``model.parameters(array_angle_offset_rad=0.5, inertia_scale_x=1.17)``.
        """
        return self.nominal.replace(**values).to_vector()

    def initial_state(
        self,
        quaternion: npt.ArrayLike = (1.0, 0.0, 0.0, 0.0),
        rate_rad_s: npt.ArrayLike = (0.0, 0.0, 0.0),
    ) -> np.ndarray:
        """State at rest (arrays undeformed) with the given attitude and body rate.

        The star tracker starts at the true attitude.
        """
        q = _vector(quaternion, 4, "quaternion")
        norm = float(np.linalg.norm(q))
        if norm == 0.0:
            raise InputShapeError("quaternion: must not be zero")
        x = np.zeros(self.layout.size)
        x[self.layout.q] = q / norm
        x[self.layout.q_st] = q / norm
        x[self.layout.omega] = _vector(rate_rad_s, 3, "rate_rad_s")
        return x


def _vector(values: npt.ArrayLike, size: int, name: str) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    if array.shape != (size,):
        raise InputShapeError(f"{name}: expected {size} numbers, got shape {array.shape}")
    if not np.all(np.isfinite(array)):
        raise InputShapeError(f"{name}: must be finite")
    return array


def select_modes(
    problem: Problem, modes: str | Sequence[str] = "all"
) -> tuple[tuple[Mode, ...], ...]:
    """The modes kept in a model, one tuple per array.

    Parameters
    ----------
    problem : Problem
    modes : "all", "first" or sequence of str
        ``"all"``: every mode of every array; ``"first"``: each array's first
        bending mode; a list of names: the modes of those names, in each array
        that has them (a name no array has is an error).
    """
    if modes == "all":
        return tuple(array.modes for array in problem.arrays)
    if modes == "first":
        return tuple(
            tuple(m for m in array.modes if (m.kind, m.order) == ("bending", 1))
            for array in problem.arrays
        )
    names = {m.name for array in problem.arrays for m in array.modes}
    unknown = [n for n in modes if n not in names]
    if unknown:
        raise ModelError(f"unknown modes {unknown}; the problem's arrays have {sorted(names)}")
    return tuple(tuple(m for m in array.modes if m.name in modes) for array in problem.arrays)


def build_model(problem: Problem, modes: str | Sequence[str] = "all") -> Model:
    """Compile the combined-body model of a problem.

    Parameters
    ----------
    problem : Problem
    modes : "all", "first" or sequence of str
        Cantilever modes kept (see :func:`select_modes`). ``"first"`` keeps each
        array's first bending mode only (the paper's truncation, a 10-state
        attitude plant).

    Returns
    -------
    Model
    """
    geometry = build_geometry(problem)
    equations = FlexibleBodyEquations(problem, geometry, select_modes(problem, modes))
    layout = equations.layout
    x = ca.SX.sym("x", layout.size)
    u = ca.SX.sym("u", len(INPUT_NAMES))
    p = ca.SX.sym("p", equations.parameters.size)
    q_ref = ca.SX.sym("q_ref", 4)
    q = ca.SX.sym("q", 4)
    t = ca.SX.sym("t")

    disturbance = problem.disturbance
    omega_orbit = 2.0 * math.pi / (disturbance.period_min * SECONDS_PER_MINUTE)
    tau_d = ca.DM(disturbance.amplitude_mNm * NM_PER_MNM) * ca.sin(
        omega_orbit * t + ca.DM(np.radians(disturbance.phase_deg))
    )
    linear, angular = equations.momenta(x, p)
    q_st = x[layout.q_st]
    return Model(
        problem=problem,
        geometry=geometry,
        layout=layout,
        dynamics=ca.Function(
            "dynamics", [x, u, p], [equations.derivatives(x, u, p)], ["x", "u", "p"], ["xdot"]
        ),
        measured_attitude=ca.Function(
            "measured_attitude",
            [x],
            [attitude_error_vector(ca.SX([1, 0, 0, 0]), q_st)],
            ["x"],
            ["y"],
        ),
        attitude_error=ca.Function(
            "attitude_error", [q_ref, q], [attitude_error_vector(q_ref, q)], ["q_ref", "q"], ["e"]
        ),
        energy=ca.Function("energy", [x, p], [equations.energy(x, p)], ["x", "p"], ["E"]),
        momenta=ca.Function("momenta", [x, p], [linear, angular], ["x", "p"], ["p_N", "h_N"]),
        mass_matrix=ca.Function("mass_matrix", [p], [equations.mass_matrix(p)], ["p"], ["M"]),
        rigid_inertia=ca.Function("rigid_inertia", [p], [equations.rigid_inertia(p)], ["p"], ["J"]),
        disturbance=ca.Function("disturbance", [t], [tau_d], ["t"], ["tau_d"]),
        nominal=equations.nominal_parameters(),
    )
