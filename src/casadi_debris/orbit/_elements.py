"""Modified equinoctial elements (MEE): conversions and the perturbed dynamics.

Elements (Walker, Ireland and Owens 1985), with a the semi-major axis, e the
eccentricity, i the inclination, Omega the node, omega the argument of perigee
and nu the true anomaly:

    p = a (1 - e^2),  f = e cos(omega + Omega),  g = e sin(omega + Omega),
    h = tan(i/2) cos Omega,  k = tan(i/2) sin Omega,  L = Omega + omega + nu.

Non-singular for circular and equatorial orbits (only i = 180 deg is), which is
why the transfer works in them. The Gauss variational equations in these
elements under an acceleration Delta = (Delta_r, Delta_t, Delta_n) in the RTN
frame (radial, transverse, orbit normal), with w = 1 + f cos L + g sin L,
s^2 = 1 + h^2 + k^2 and q = sqrt(p / mu) (Betts, *Practical Methods for Optimal
Control*, 2nd ed., Sec. 6.3):

    p' = 2 p q Delta_t / w
    f' = q [ Delta_r sin L + ((w + 1) cos L + f) Delta_t / w - (h sin L - k cos L) g Delta_n / w ]
    g' = q [-Delta_r cos L + ((w + 1) sin L + g) Delta_t / w + (h sin L - k cos L) f Delta_n / w ]
    h' = q s^2 Delta_n cos L / (2 w)
    k' = q s^2 Delta_n sin L / (2 w)
    L' = sqrt(mu p) (w / p)^2 + q (h sin L - k cos L) Delta_n / w

The J2 acceleration in RTN, r = p / w (Betts, Eq. 6.23):

    Delta_r = -3 mu J2 Re^2 / (2 r^4) [1 - 12 (h sin L - k cos L)^2 / s^4]
    Delta_t = -12 mu J2 Re^2 / r^4 (h sin L - k cos L)(h cos L + k sin L) / s^4
    Delta_n = -6 mu J2 Re^2 / r^4 (1 - h^2 - k^2)(h sin L - k cos L) / s^4

The thrust adds F / m along its RTN direction and burns m' = -|F| / (eta c),
with c = Isp g0 the exhaust speed and eta <= 1 the share of the engines'
thrust that ends up as net force (engines throttled to cancel a torque).
Everything is SI (m, s, kg, rad).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

# Earth's second zonal harmonic (EGM2008, unnormalised). Not a problem-file value:
# it is the Earth's, like the rotation rate in environment.orbit.
EARTH_J2 = 1.08262668e-3
N_ELEMENTS = 6  # p, f, g, h, k, L


def mee_from_cartesian(
    position_m: np.ndarray, velocity_m_s: np.ndarray, mu_m3_s2: float
) -> np.ndarray:
    """Modified equinoctial elements of a Cartesian state (inertial frame).

    Parameters
    ----------
    position_m, velocity_m_s : array_like, shape (3,)
    mu_m3_s2 : float

    Returns
    -------
    ndarray, shape (6,)
        ``[p (m), f, g, h, k, L (rad, in [0, 2 pi))]``.
    """
    r = np.asarray(position_m, dtype=float)
    v = np.asarray(velocity_m_s, dtype=float)
    momentum = np.cross(r, v)
    p = float(momentum @ momentum) / mu_m3_s2
    normal = momentum / np.linalg.norm(momentum)
    h = -normal[1] / (1.0 + normal[2])
    k = normal[0] / (1.0 + normal[2])
    f_axis, g_axis = _equinoctial_axes(h, k)
    eccentricity = np.cross(v, momentum) / mu_m3_s2 - r / np.linalg.norm(r)
    longitude = np.arctan2(r @ g_axis, r @ f_axis) % (2.0 * np.pi)
    return np.array([p, eccentricity @ f_axis, eccentricity @ g_axis, h, k, longitude])


def cartesian_from_mee(elements: np.ndarray, mu_m3_s2: float) -> tuple[np.ndarray, np.ndarray]:
    """Position [m] and velocity [m/s], inertial frame, of modified equinoctial elements.

    Parameters
    ----------
    elements : array_like, shape (6,)
        ``[p (m), f, g, h, k, L (rad)]``.
    mu_m3_s2 : float

    Returns
    -------
    position_m, velocity_m_s : ndarray, shape (3,)
    """
    p, f, g, h, k, longitude = (float(x) for x in elements)
    f_axis, g_axis = _equinoctial_axes(h, k)
    w = 1.0 + f * np.cos(longitude) + g * np.sin(longitude)
    radius = p / w
    position = radius * (np.cos(longitude) * f_axis + np.sin(longitude) * g_axis)
    speed = np.sqrt(mu_m3_s2 / p)
    velocity = speed * (-(g + np.sin(longitude)) * f_axis + (f + np.cos(longitude)) * g_axis)
    return position, velocity


def _equinoctial_axes(h: float, k: float) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors f and g of the equinoctial frame (in the orbit plane)."""
    s2 = 1.0 + h * h + k * k
    f_axis = np.array([1.0 - k * k + h * h, 2.0 * h * k, -2.0 * k]) / s2
    g_axis = np.array([2.0 * h * k, 1.0 + k * k - h * h, 2.0 * h]) / s2
    return f_axis, g_axis


def keplerian_from_mee(elements: np.ndarray) -> dict[str, float]:
    """Semi-major axis [m], eccentricity, inclination [rad] and node [rad] of MEE."""
    p, f, g, h, k = (float(x) for x in elements[:5])
    e2 = f * f + g * g
    return {
        "semi_major_axis_m": p / (1.0 - e2),
        "eccentricity": float(np.sqrt(e2)),
        "inclination_rad": 2.0 * float(np.arctan(np.hypot(h, k))),
        "node_rad": float(np.arctan2(k, h)) % (2.0 * np.pi),
    }


def mee_circular(radius_m: float, inclination_rad: float, node_rad: float = 0.0) -> np.ndarray:
    """The five slow elements ``[p, f, g, h, k]`` of a circular orbit, shape (5,)."""
    t = np.tan(inclination_rad / 2.0)
    return np.array([radius_m, 0.0, 0.0, t * np.cos(node_rad), t * np.sin(node_rad)])


def gauss_mee_rates(x: ca.SX, acceleration_rtn: ca.SX, mu: ca.SX | float) -> ca.SX:
    """Gauss variational equations in MEE (module docstring), symbolic.

    Parameters
    ----------
    x : casadi.SX, shape (6, 1)
        ``[p, f, g, h, k, L]``.
    acceleration_rtn : casadi.SX, shape (3, 1)
        Perturbing acceleration, RTN [m/s^2].
    mu : float or casadi.SX

    Returns
    -------
    rates : casadi.SX, shape (6, 1)
        d[p, f, g, h, k, L]/dt.
    """
    p, f, g, h, k, lon = (x[i] for i in range(N_ELEMENTS))
    a_r, a_t, a_n = acceleration_rtn[0], acceleration_rtn[1], acceleration_rtn[2]
    cos_l, sin_l = ca.cos(lon), ca.sin(lon)
    w = 1.0 + f * cos_l + g * sin_l
    s2 = 1.0 + h * h + k * k
    q = ca.sqrt(p / mu)
    hk = h * sin_l - k * cos_l
    return ca.vertcat(
        2.0 * p * q * a_t / w,
        q * (a_r * sin_l + ((w + 1.0) * cos_l + f) * a_t / w - hk * g * a_n / w),
        q * (-a_r * cos_l + ((w + 1.0) * sin_l + g) * a_t / w + hk * f * a_n / w),
        q * s2 * a_n * cos_l / (2.0 * w),
        q * s2 * a_n * sin_l / (2.0 * w),
        ca.sqrt(mu * p) * (w / p) ** 2 + q * hk * a_n / w,
    )


def j2_acceleration_rtn(
    x: ca.SX, mu: ca.SX | float, radius_m: ca.SX | float, j2: ca.SX | float
) -> ca.SX:
    """J2 acceleration in RTN [m/s^2] at MEE ``x`` (module docstring), shape (3, 1)."""
    p, f, g, h, k, lon = (x[i] for i in range(N_ELEMENTS))
    cos_l, sin_l = ca.cos(lon), ca.sin(lon)
    w = 1.0 + f * cos_l + g * sin_l
    r = p / w
    s4 = (1.0 + h * h + k * k) ** 2
    hk = h * sin_l - k * cos_l
    scale = mu * j2 * radius_m**2 / r**4
    return ca.vertcat(
        -1.5 * scale * (1.0 - 12.0 * hk**2 / s4),
        -12.0 * scale * hk * (h * cos_l + k * sin_l) / s4,
        -6.0 * scale * (1.0 - h * h - k * k) * hk / s4,
    )


def mee_dynamics() -> ca.Function:
    """The MEE equations with J2 and thrust, and the mass flow, as one ``casadi.Function``.

    ``mee_dynamics(x, m, force_rtn, p) -> (xdot, mdot)`` with

    - ``x`` (6): ``[p (m), f, g, h, k, L (rad)]``; ``m``: mass [kg];
    - ``force_rtn`` (3): net thrust force in RTN [N];
    - ``p`` (5): ``[mu (m^3/s^2), Re (m), J2, c = Isp g0 (m/s), eta]``;
    - ``xdot`` (6), ``mdot`` = -|F| / (eta c) [kg/s].

    Example
    -------
    >>> import numpy as np
    >>> f = mee_dynamics()
    >>> x = [6.928e6, 0, 0, 1.1, 0.1, 0.0]
    >>> xdot, mdot = f(x, 600.0, [0, 2.5e-3, 0], [3.986e14, 6.378e6, EARTH_J2, 9806.65, 1.0])
    >>> float(mdot) * 1e9  # kg/s x 1e9
    -254.9...
    """
    x = ca.SX.sym("x", N_ELEMENTS)
    mass = ca.SX.sym("m")
    force = ca.SX.sym("force_rtn", 3)
    params = ca.SX.sym("p", 5)
    mu, radius, j2, exhaust, efficiency = (params[i] for i in range(5))
    acceleration = j2_acceleration_rtn(x, mu, radius, j2) + force / mass
    xdot = gauss_mee_rates(x, acceleration, mu)
    mdot = -ca.norm_2(force) / (efficiency * exhaust)
    return ca.Function(
        "mee_dynamics",
        [x, mass, force, params],
        [xdot, mdot],
        ["x", "m", "force_rtn", "p"],
        ["xdot", "mdot"],
    )
