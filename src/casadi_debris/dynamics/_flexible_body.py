"""Symbolic equations of motion of the combined body (hub + CubeSats + flexible arrays).

Hybrid coordinates (Likins; see also the paper's eq. for a single array)
-----------------------------------------------------------------------
Generalised velocities nu = [v_B, omega_BN_B, eta_dot]: velocity of the
reference point (the undeformed combined CoG, origin of B), body rate, and
the rates of the arrays' cantilever modal coordinates eta (mass-normalised,
array-major order). With the undeformed CoG as reference there is no rigid
translation/rotation coupling, and the mass matrix is

    M = [[m I3,  0,   Pt^T],
         [0,     J,   Hr^T],
         [Pt,    Hr,  I   ]]

with J the full rigid inertia (hub + CubeSats, scaled per axis by the
uncertain factors, plus both arrays as rigid bodies at angle theta_SA) and
Pt, Hr (n_eta x 3) the translational and rotational modal participation
about the CoG. Linear momentum p = m v + Pt^T eta_dot and angular momentum
h = J omega + Hr^T eta_dot obey, in B,

    p_dot + omega x p = F
    h_dot + omega x h + v x p = tau + tau_d
    eta_ddot + Pt v_dot + Hr omega_dot + 2 zeta Omega eta_dot + Omega^2 eta = 0

which conserve kinetic plus strain energy exactly when F = tau = 0 and zeta = 0.

Modelling choices and limits (kept explicit):

- Participation comes from uniform-beam mode shapes with the array's mass and
  length, while the rigid inertia uses the problem's array inertia (the
  paper's 62 kg m^2 about the width axis exceeds a uniform 2.5 m beam's
  21.9): the difference is rigid, non-participating mass. With an inertia
  consistent with a uniform beam the anti-phase bending mode would sit at
  about 11 rad/s instead of 9.0.
- Damping zeta acts on the cantilever coordinates, as the paper states it;
  the assembled modes' damping ratios therefore differ (0.005 to 0.008).
- M is constant (first-order hybrid coordinates): no centrifugal forcing or
  stiffening of the modes and no inertia change with deflection. Valid for
  body rates well below the first mode (|omega| << 5.6 rad/s), i.e. for the
  slews and pointing of the paper, not for a fast tumble.
Attitude: q_BN (scalar first), q_dot = 1/2 q (x) [0, omega]. The star tracker
is a first-order low pass on the attitude, written on the quaternion so that
it stays valid for large angles: q_ST_dot = 1/2 q_ST (x) [0, b e], with e the
doubled short-way vector part of q_ST^-1 (x) q_BN and b its bandwidth.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca

from casadi_debris.config import Mode, Problem
from casadi_debris.dynamics._attitude import (
    attitude_error_vector,
    quaternion_product,
    rotation_matrix,
)
from casadi_debris.dynamics._cantilever import shape_integrals
from casadi_debris.dynamics._parameters import ParameterLayout, Parameters
from casadi_debris.geometry import Geometry, array_axes, array_rigid_inertia

INPUT_NAMES = (
    "torque_x_Nm",
    "torque_y_Nm",
    "torque_z_Nm",
    "disturbance_x_Nm",
    "disturbance_y_Nm",
    "disturbance_z_Nm",
    "force_x_N",
    "force_y_N",
    "force_z_N",
)


@dataclass(frozen=True)
class StateLayout:
    """Where each part of the state vector lives.

    Attributes
    ----------
    n_eta : int
        Number of modal coordinates (arrays x modes).
    mode_labels : tuple of (int, str)
        (array number from 1, mode name) of each modal coordinate.
    """

    n_eta: int
    mode_labels: tuple[tuple[int, str], ...]

    @property
    def q(self) -> slice:
        return slice(0, 4)

    @property
    def omega(self) -> slice:
        return slice(4, 7)

    @property
    def v(self) -> slice:
        return slice(7, 10)

    @property
    def eta(self) -> slice:
        return slice(10, 10 + self.n_eta)

    @property
    def eta_dot(self) -> slice:
        return slice(10 + self.n_eta, 10 + 2 * self.n_eta)

    @property
    def q_st(self) -> slice:
        return slice(10 + 2 * self.n_eta, 14 + 2 * self.n_eta)

    @property
    def size(self) -> int:
        return 14 + 2 * self.n_eta

    def names(self) -> list[str]:
        """One name per state, in order."""
        modal = [f"array{a}_{m}" for a, m in self.mode_labels]
        return (
            ["q0_BN", "q1_BN", "q2_BN", "q3_BN"]
            + ["omega_x", "omega_y", "omega_z", "v_x", "v_y", "v_z"]
            + [f"eta_{n}" for n in modal]
            + [f"eta_dot_{n}" for n in modal]
            + ["q0_ST", "q1_ST", "q2_ST", "q3_ST"]
        )


class FlexibleBodyEquations:
    """Symbolic mass properties and equations of motion for one mode selection.

    Parameters
    ----------
    problem : Problem
    geometry : Geometry
    modes : tuple of tuple of Mode
        The cantilever modes kept, one tuple per array.
    """

    def __init__(
        self, problem: Problem, geometry: Geometry, modes: tuple[tuple[Mode, ...], ...]
    ) -> None:
        self.problem = problem
        self.geometry = geometry
        self.modes = modes
        self.layout = StateLayout(
            n_eta=sum(len(kept) for kept in modes),
            mode_labels=tuple((a + 1, m.name) for a, kept in enumerate(modes) for m in kept),
        )
        self.parameters = ParameterLayout.for_problem(problem)

    def nominal_parameters(self) -> Parameters:
        """The parameters at the problem's nominal values."""
        layout = self.parameters
        return Parameters(
            layout=layout,
            inertia_scale=(1.0, 1.0, 1.0),
            mass_kg=self.geometry.mass_kg,
            array_angle_offsets_rad=(0.0,) * layout.array_angles,
            bending_frequency_scale=1.0 if layout.has_bending_scale else None,
        )

    def rigid_inertia(self, p: ca.SX) -> ca.SX:
        """Full rigid inertia about the CoG: scaled hub + CubeSats plus arrays, (3, 3)."""
        scale = ca.sqrt(self.parameters.inertia_scale(p))
        hub_cubesats = ca.DM(self.geometry.inertia_hub_cubesats_kgm2) * (scale @ scale.T)
        arrays = sum(
            (
                array_rigid_inertia(array, hinge, self._angle(index, p))
                for index, (array, hinge) in enumerate(
                    zip(self.problem.arrays, self.geometry.hinges_m, strict=True)
                )
            ),
            ca.SX.zeros(3, 3),
        )
        return hub_cubesats + arrays

    def _angle(self, index: int, p: ca.SX) -> ca.SX:
        """Array ``index``'s angle theta_SA: its nominal angle plus the parameters' offset."""
        nominal = math.radians(self.problem.arrays[index].angle_deg)
        return nominal + self.parameters.array_angle_offset_rad(p, index)

    def participation(self, p: ca.SX) -> tuple[ca.SX, ca.SX]:
        """Translational and rotational (about the CoG) modal participation, (n_eta, 3) each."""
        rows_t, rows_r = [], []
        for index, (array, hinge, kept) in enumerate(
            zip(self.problem.arrays, self.geometry.hinges_m, self.modes, strict=True)
        ):
            if not kept:
                continue
            e_length, _, normal = array_axes(array.direction, self._angle(index, p))
            sqrt_mass = math.sqrt(array.mass_kg)
            for mode in kept:
                integrals = shape_integrals(mode.kind, mode.order)
                translation: ca.SX | ca.DM
                rotation: ca.SX | ca.DM
                if mode.kind == "bending":
                    translation = sqrt_mass * integrals.first * normal
                    rotation = ca.cross(ca.DM(hinge), translation) + (
                        sqrt_mass * array.length_m * integrals.moment * ca.cross(e_length, normal)
                    )
                else:  # torsion: twist about the length axis, no net translation
                    translation = ca.DM.zeros(3)
                    rotation = math.sqrt(array.inertia_kgm2[0]) * integrals.first * e_length
                rows_t.append(translation.T)
                rows_r.append(rotation.T)
        if not rows_t:  # rigid model: no modes kept
            return ca.SX(0, 3), ca.SX(0, 3)
        return ca.vertcat(*rows_t), ca.vertcat(*rows_r)

    def modal_frequencies(self, p: ca.SX) -> ca.SX:
        """Cantilever frequency of each modal coordinate [rad/s], (n_eta, 1)."""
        frequencies = [
            m.omega_rad_s * self.parameters.bending_frequency_scale(p)
            if (m.kind, m.order) == ("bending", 1)
            else ca.SX(m.omega_rad_s)
            for kept in self.modes
            for m in kept
        ]
        return ca.vertcat(*frequencies) if frequencies else ca.SX(0, 1)

    def damping_ratios(self) -> ca.DM:
        """Damping ratio of each modal coordinate (its array's), (n_eta, 1)."""
        arrays = zip(self.problem.arrays, self.modes, strict=True)
        ratios = [array.damping_ratio for array, kept in arrays for _ in kept]
        return ca.DM(ratios) if ratios else ca.DM(0, 1)

    def mass_matrix(self, p: ca.SX) -> ca.SX:
        """Generalised mass matrix for nu = [v, omega, eta_dot], (6 + n_eta) square."""
        pt, hr = self.participation(p)
        n = self.layout.n_eta
        top = ca.horzcat(self.parameters.mass_kg(p) * ca.SX.eye(3), ca.SX.zeros(3, 3), pt.T)
        middle = ca.horzcat(ca.SX.zeros(3, 3), self.rigid_inertia(p), hr.T)
        bottom = ca.horzcat(pt, hr, ca.SX.eye(n))
        return ca.vertcat(top, middle, bottom)

    def derivatives(self, x: ca.SX, u: ca.SX, p: ca.SX) -> ca.SX:
        """State derivative x_dot(x, u, p), shape (layout.size, 1)."""
        lay = self.layout
        q, omega, v = x[lay.q], x[lay.omega], x[lay.v]
        eta, eta_dot, q_st = x[lay.eta], x[lay.eta_dot], x[lay.q_st]
        torque, disturbance, force = u[0:3], u[3:6], u[6:9]

        pt, hr = self.participation(p)
        inertia = self.rigid_inertia(p)
        mass = self.parameters.mass_kg(p)
        frequencies = self.modal_frequencies(p)
        zeta = self.damping_ratios()

        linear_momentum = mass * v + pt.T @ eta_dot
        angular_momentum = inertia @ omega + hr.T @ eta_dot
        rhs_v = force - ca.cross(omega, linear_momentum)
        rhs_omega = (
            torque + disturbance - ca.cross(omega, angular_momentum) - ca.cross(v, linear_momentum)
        )
        rhs_eta = -2.0 * zeta * frequencies * eta_dot - frequencies**2 * eta

        # Block elimination of eta_ddot = rhs_eta - Pt v_dot - Hr omega_dot leaves a
        # 6 x 6 system for the rigid accelerations (the Schur complement of M).
        coupling = ca.horzcat(pt, hr)
        rigid_mass = ca.diagcat(mass * ca.SX.eye(3), inertia) - coupling.T @ coupling
        rigid_rhs = ca.vertcat(rhs_v, rhs_omega) - coupling.T @ rhs_eta
        rigid_acceleration = ca.solve(rigid_mass, rigid_rhs)
        eta_ddot = rhs_eta - coupling @ rigid_acceleration

        q_dot = 0.5 * quaternion_product(q, ca.vertcat(0, omega))
        sensor_rate = self.problem.sensor.star_tracker_bandwidth_rad_s * attitude_error_vector(
            q_st, q
        )
        q_st_dot = 0.5 * quaternion_product(q_st, ca.vertcat(0, sensor_rate))
        return ca.vertcat(
            q_dot, rigid_acceleration[3:6], rigid_acceleration[0:3], eta_dot, eta_ddot, q_st_dot
        )

    def energy(self, x: ca.SX, p: ca.SX) -> ca.SX:
        """Kinetic plus modal strain energy [J]."""
        lay = self.layout
        nu = ca.vertcat(x[lay.v], x[lay.omega], x[lay.eta_dot])
        frequencies = self.modal_frequencies(p)
        return 0.5 * nu.T @ self.mass_matrix(p) @ nu + 0.5 * ca.sumsqr(frequencies * x[lay.eta])

    def momenta(self, x: ca.SX, p: ca.SX) -> tuple[ca.SX, ca.SX]:
        """Linear momentum and angular momentum about the reference point, inertial components.

        The reference point is the undeformed combined CoG (origin of B). The
        angular momentum is conserved without torque while the linear momentum
        is zero (a free body started with p = 0 keeps p = 0).
        """
        lay = self.layout
        pt, hr = self.participation(p)
        eta_dot = x[lay.eta_dot]
        rotation = rotation_matrix(x[lay.q])
        linear = self.parameters.mass_kg(p) * x[lay.v] + pt.T @ eta_dot
        angular = self.rigid_inertia(p) @ x[lay.omega] + hr.T @ eta_dot
        return rotation @ linear, rotation @ angular
