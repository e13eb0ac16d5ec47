"""Orbit-averaged MEE dynamics of a low-thrust spiral with J2, and Edelbaum's analytic transfer.

A transfer from 550 to 685 km at ~2.5 mN on ~670 kg takes over a year, some
6,000 revolutions: a direct transcription of the osculating equations would need
hundreds of thousands of nodes. Over one revolution the five slow elements
``x = [p, f, g, h, k]`` barely move, so the transfer is flown on their
revolution averages (first-order averaging, e.g. Kechichian 1997; Betts Sec. 6.3):

    dx/dt = (1/T) oint x'(x, L, u(L)) dL / L'(x, L, u(L)),
    T = oint dL / L',

with ``x'`` and ``L'`` the Gauss equations with J2 and thrust of
:mod:`casadi_debris.orbit._elements`. The integral is taken by Gauss-Legendre
quadrature in the argument of latitude ``u = L - Omega``, on the two half
revolutions where the control law is smooth. J2 enters through its averaged
(secular) rates, the node's precession above all.

The control is Edelbaum's law, constant over a revolution: the thrust lies in
the plane of the velocity and the orbit normal, at a yaw ``beta`` out of the
plane, and the out-of-plane part flips sign at the antinodes,

    direction_RTN = [0, cos beta, sign(cos u) sin beta],

so that it always turns the plane the same way; a throttle ``eta`` in [0, 1]
scales the force. Edelbaum's analytic transfer between circular orbits under
this law (Edelbaum 1961; Kechichian 1997):

    dv = sqrt(V0^2 - 2 V0 V1 cos(pi/2 di) + V1^2),
    tan beta0 = sin(pi/2 di) / (V0 / V1 - cos(pi/2 di)).
"""

from __future__ import annotations

import math
from typing import Any

import casadi as ca
import numpy as np

from casadi_debris.orbit._elements import gauss_mee_rates, j2_acceleration_rtn, keplerian_from_mee
from casadi_debris.units import M_PER_KM

# Gauss-Legendre nodes per half revolution: the integrands are smooth there, and
# 12 nodes integrate the J2 and thrust terms of a near-circular orbit to ~1e-12.
QUADRATURE_NODES = 12
N_SLOW = 5  # p, f, g, h, k
N_AVERAGED_PARAMS = 5  # mu, Re, J2, force, flow


def averaged_dynamics(nodes: int = QUADRATURE_NODES) -> ca.Function:
    """Revolution-averaged MEE rates under Edelbaum's steering law, as a ``casadi.Function``.

    ``averaged_mee(x, m, u, p) -> (xdot, mdot)`` with

    - ``x`` (5): ``[p (m), f, g, h, k]``; ``m``: mass [kg];
    - ``u`` (2): ``[beta (rad), eta]``, yaw out of the orbit plane and throttle;
    - ``p`` (5): ``[mu (m^3/s^2), Re (m), J2, force (N), flow (kg/s)]``, the
      force and propellant flow at full throttle;
    - ``xdot`` (5) [per s], ``mdot`` = -eta flow [kg/s].

    Parameters
    ----------
    nodes : int
        Gauss-Legendre nodes per half revolution.
    """
    x = ca.SX.sym("x", N_SLOW)
    mass = ca.SX.sym("m")
    control = ca.SX.sym("u", 2)
    params = ca.SX.sym("p", N_AVERAGED_PARAMS)
    mu, radius, j2, force, flow = (params[i] for i in range(N_AVERAGED_PARAMS))
    beta, throttle = control[0], control[1]
    node = ca.atan2(x[4], x[3])
    points, weights = np.polynomial.legendre.leggauss(nodes)
    rates: ca.SX = ca.SX.zeros(N_SLOW)
    period: ca.SX = ca.SX(0.0)
    for centre, sign in ((0.0, 1.0), (math.pi, -1.0)):
        for point, weight in zip(points, weights, strict=True):
            latitude = centre + 0.5 * math.pi * point
            state = ca.vertcat(x, node + latitude)
            thrust = throttle * force / mass * ca.vertcat(0.0, ca.cos(beta), sign * ca.sin(beta))
            acceleration = j2_acceleration_rtn(state, mu, radius, j2) + thrust
            xdot = gauss_mee_rates(state, acceleration, mu)
            dt_dl = 1.0 / xdot[5]
            rates += float(weight) * xdot[:N_SLOW] * dt_dl
            period += float(weight) * dt_dl
    return ca.Function(
        "averaged_mee",
        [x, mass, control, params],
        [rates / period, -throttle * flow],
        ["x", "m", "u", "p"],
        ["xdot", "mdot"],
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


def edelbaum_yaw(
    mu_m3_s2: float, radius_m: float, target_radius_m: float, inclination_change_rad: float
) -> float:
    """Edelbaum's initial yaw beta0 [rad] from a circular orbit to another, signed as di.

    In [0, pi] in magnitude: beyond pi/2 the thrust slows the orbit (lowering).
    """
    ratio = math.sqrt(target_radius_m / radius_m)  # V0 / V1
    angle = 0.5 * math.pi * abs(inclination_change_rad)
    return math.copysign(
        math.atan2(math.sin(angle), ratio - math.cos(angle)), inclination_change_rad
    )


def averaged_step(
    dynamics: ca.Function,
    x: Any,
    mass: Any,
    control: Any,
    params: Any,
    step_s: Any,
    steps: int = 1,
) -> tuple[Any, Any]:
    """Classical RK4 over ``step_s`` (in ``steps`` equal steps) of the averaged dynamics.

    Works on numbers (``casadi.DM``) and on symbols (``casadi.MX``) alike, so the
    guidance law and the optimal control problem integrate with one scheme.

    Parameters
    ----------
    dynamics : casadi.Function
        :func:`averaged_dynamics`.
    x : array_like or casadi.MX, shape (5,)
        Slow MEE.
    mass : float or casadi.MX
        [kg].
    control, params
        As for :func:`averaged_dynamics` (lists, ``casadi.DM`` or ``casadi.MX``).
    step_s : float or casadi.MX
        Length of the whole step [s].
    steps : int
        RK4 steps within it.

    Returns
    -------
    x, mass
        After the step (``casadi.DM`` for numbers, ``casadi.MX`` for symbols).
    """
    h = step_s / steps
    state = ca.vertcat(x, mass)

    def rate(s: Any) -> Any:
        xdot, mdot = dynamics(s[:N_SLOW], s[N_SLOW], control, params)
        return ca.vertcat(xdot, mdot)

    for _ in range(steps):
        k1 = rate(state)
        k2 = rate(state + 0.5 * h * k1)
        k3 = rate(state + 0.5 * h * k2)
        k4 = rate(state + h * k3)
        state = state + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    return state[:N_SLOW], state[N_SLOW]


def radius_inclination(x: np.ndarray) -> tuple[float, float]:
    """Semi-major axis [m] and inclination [rad] of slow elements ``[p, f, g, h, k]``."""
    elements = keplerian_from_mee(np.ravel(x))
    return elements["semi_major_axis_m"], elements["inclination_rad"]
