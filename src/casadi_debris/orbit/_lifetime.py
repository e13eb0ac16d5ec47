"""Orbital decay under drag (and a retrograde low-thrust burn), averaged over each orbit.

Equations
---------
Gauss's equations for an acceleration f_t along the velocity (Vallado,
*Fundamentals of Astrodynamics*, 4th ed., eq. 9-24),

    da/dt = 2 a^2 v f_t / mu,    de/dt = 2 (e + cos nu) f_t / v,

averaged over one orbit in the eccentric anomaly E (dM = (1 - e cos E) dE,
``e + cos nu = (1 - e^2) cos E / (1 - e cos E)``), with the orbit's elements
held over the orbit:

    <da/dt> = (a^2 / (2 pi mu)) int 2 v f_t (1 - e cos E) dE
    <de/dt> = (1 / (2 pi))      int 2 f_t (1 - e^2) cos E / v dE

- Drag: ``f_t = -rho(h) w^2 / (2 B)``, B = m / (C_D A), w = v - omega_E r cos i the
  speed relative to an atmosphere turning with the Earth (its along-track part,
  exact for a circular orbit), rho the orbit- and day-averaged density of
  :mod:`~casadi_debris.orbit._atmosphere` at h = r - R_E (R_E the equatorial
  radius; the table gives NRLMSIS each orbit point's geodetic altitude, which
  is up to 21 km above h near the poles). Integrated over the
  whole orbit by the trapezoidal rule (spectrally
  accurate for a periodic integrand; :data:`NODES_BY_SWING`).
- Thrust: ``f_t = -T / m`` on an arc of eccentric anomaly centred on apogee
  (``|E - pi| <= half_width``; pi is the whole orbit, a circular spiral), by
  Gauss-Legendre on the arc. The engines fire the arc's share of the time.
  Mass falls as ``dm/dt = -T duty / (Isp g0)``.

The state (a, e, m, J) is integrated by ``scipy.integrate.solve_ivp`` (RK45)
until re-entry: perigee altitude at :data:`REENTRY_PERIGEE_KM` (below it the
debris comes down within days; the last hours are left out of the lifetime).
J is the impulse the engines gave; the burn ends when J reaches its target.
These are the averaged equations King-Hele's lifetime theory expands in
series; integrating them numerically needs no assumption on the scale height.
J2 leaves the mean a and e unchanged and is left out.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from casadi_debris.config import Problem
from casadi_debris.environment import EARTH_ROTATION_RAD_S
from casadi_debris.units import M_PER_KM, SECONDS_PER_YEAR

REENTRY_PERIGEE_KM = 120.0
# Trapezoid nodes over the orbit, by the altitude swing a e: the integrand goes as
# exp((a e / H) cos E), whose n-th Fourier term falls as (a e / 2H)^n / n!, so that
# 8 nodes are exact to rounding below a e = 5 km and 32 below 150 km (H >= 20 km).
NODES_BY_SWING = ((5e3, 8), (150e3, 32), (math.inf, 96))
ARC_NODES = 12
DEFAULT_HORIZON_YEARS = 200.0
RTOL = 1e-6

DensityFunction = Callable[[np.ndarray, float], np.ndarray]
"""``density(altitude_m, time_s) -> rho [kg/m^3]``, altitude of any shape."""


@dataclass(frozen=True)
class Earth:
    """The Earth the orbit is about: gravity, radius, spin.

    Attributes
    ----------
    mu_m3_s2, radius_m, rotation_rad_s : float
    """

    mu_m3_s2: float
    radius_m: float
    rotation_rad_s: float = EARTH_ROTATION_RAD_S

    @classmethod
    def from_problem(cls, problem: Problem) -> Earth:
        """The problem's ``[constants]``."""
        constants = problem.constants
        return cls(constants.earth_mu_km3_s2 * M_PER_KM**3, constants.earth_radius_km * M_PER_KM)


@dataclass(frozen=True)
class RetrogradeBurn:
    """A retrograde low-thrust burn: thrust levels used one after another.

    Attributes
    ----------
    thrust_N : tuple of float
        Thrust of each segment (a set of engines along one body direction).
    impulse_Ns : tuple of float
        Impulse each segment can give; the last one is extended if the target asks more.
    target_impulse_Ns : float
        Where the burn ends.
    exhaust_speed_m_s : float
        Isp g0.
    drag_area_m2 : tuple of float
        Drag area of each segment (the body held with that segment's push against
        the velocity).
    half_width_rad : float
        Of the arc of eccentric anomaly, centred on apogee, the engines fire on
        (pi: all the orbit).
    """

    thrust_N: tuple[float, ...]
    impulse_Ns: tuple[float, ...]
    target_impulse_Ns: float
    exhaust_speed_m_s: float
    drag_area_m2: tuple[float, ...]
    half_width_rad: float = math.pi


@dataclass(frozen=True, eq=False)
class DecayHistory:
    """The averaged orbit over time, from the start of a burn (or of the decay).

    Attributes
    ----------
    time_s : ndarray, shape (n,)
    semi_major_axis_m, eccentricity, mass_kg, impulse_Ns : ndarray, shape (n,)
    burn_end_s : float
        When the burn ended (0 without one).
    reentry_s : float
        Time of re-entry; ``inf`` when not within the horizon.
    radius_m : float
        The Earth's.
    """

    time_s: np.ndarray
    semi_major_axis_m: np.ndarray
    eccentricity: np.ndarray
    mass_kg: np.ndarray
    impulse_Ns: np.ndarray
    burn_end_s: float
    reentry_s: float
    radius_m: float = field(default=6378137.0)

    @property
    def reentry_years(self) -> float:
        """Lifetime [years of 365.25 days]; ``inf`` if beyond the horizon."""
        return self.reentry_s / SECONDS_PER_YEAR

    @property
    def perigee_altitude_m(self) -> np.ndarray:
        return self.semi_major_axis_m * (1.0 - self.eccentricity) - self.radius_m

    @property
    def apogee_altitude_m(self) -> np.ndarray:
        return self.semi_major_axis_m * (1.0 + self.eccentricity) - self.radius_m


def _drag_rates(
    a: float,
    e: float,
    rho_of: Callable[[np.ndarray], np.ndarray],
    k: float,
    earth: Earth,
    cos_i: float,
) -> tuple[float, float]:
    """Orbit-averaged (da/dt, de/dt) of drag, ``k = 1 / B`` [m^2/kg]."""
    swing = a * e
    cos_e = next(nodes for limit, nodes in _COS_NODES if swing < limit)
    mu = earth.mu_m3_s2
    r = a - a * e * cos_e
    v = np.sqrt(mu * (2.0 / r - 1.0 / a))
    w = v - earth.rotation_rad_s * cos_i * r
    # f_t = -k rho w^2 / 2; the means below carry its factor -k/2 outside.
    drag = rho_of(r - earth.radius_m) * w * w
    scale = -0.5 * k / cos_e.size
    da = 2.0 * a * a / mu * scale * float(np.dot(drag * v, 1.0 - e * cos_e))
    de = 2.0 * (1.0 - e * e) * scale * float(np.dot(drag / v, cos_e))
    return da, de


_COS_NODES = tuple(
    (limit, np.cos((np.arange(n) + 0.5) * (2.0 * math.pi / n))) for limit, n in NODES_BY_SWING
)
_GL_X, _GL_W = np.polynomial.legendre.leggauss(ARC_NODES)


def _thrust_rates(
    a: float, e: float, acceleration: float, half_width: float, mu: float
) -> tuple[float, float, float]:
    """Orbit-averaged (da/dt, de/dt) of a retrograde acceleration on the apogee arc, and the
    share of the time the engines fire."""
    E = math.pi + half_width * _GL_X
    weights = _GL_W * half_width / (2.0 * math.pi)
    cos_e = np.cos(E)
    r = a * (1.0 - e * cos_e)
    v = np.sqrt(mu * (2.0 / r - 1.0 / a))
    f_t = -acceleration
    da = a * a / mu * float(weights @ (2.0 * v * f_t * (1.0 - e * cos_e)))
    de = float(weights @ (2.0 * f_t * (1.0 - e * e) * cos_e / v))
    duty = float(weights @ (1.0 - e * cos_e))
    return da, de, duty


def propagate_decay(
    semi_major_axis_m: float,
    eccentricity: float,
    mass_kg: float,
    *,
    drag_area_m2: float,
    drag_coefficient: float,
    density: DensityFunction,
    earth: Earth,
    inclination_rad: float,
    burn: RetrogradeBurn | None = None,
    horizon_years: float = DEFAULT_HORIZON_YEARS,
) -> DecayHistory:
    """Integrate the averaged orbit from a (possibly burning) start to re-entry.

    Parameters
    ----------
    semi_major_axis_m, eccentricity, mass_kg : float
        At the start.
    drag_area_m2, drag_coefficient : float
        Of the decay after the burn (tumbling, say).
    density : callable
        ``density(altitude_m, time_s)``.
    earth : Earth
    inclination_rad : float
        For the atmosphere's rotation.
    burn : RetrogradeBurn, optional
        Fired first, from t = 0 (its own drag areas while it fires).
    horizon_years : float
        Give up after this long (re-entry ``inf``).

    Returns
    -------
    DecayHistory
    """
    rates = _AveragedRates(
        drag_area_m2, drag_coefficient, density, earth, math.cos(inclination_rad), burn
    )
    horizon = horizon_years * SECONDS_PER_YEAR
    y0 = np.array([semi_major_axis_m, eccentricity, mass_kg, 0.0])
    if rates.down(0.0, y0) <= 0.0:
        return _history([np.array([0.0])], [y0[:, None]], 0.0, 0.0, earth)
    times, states, burn_end, step = [], [], 0.0, None
    # One integration per thrust segment (the thrust jumps between them), each starting
    # with the step the last one ended with.
    for segment, stop in _burn_stops(burn):
        part = _integrate(rates, (burn_end, horizon), y0, segment, stop, step)
        times.append(part.t)
        states.append(part.y)
        burn_end = float(part.t[-1])
        if _event_fired(part.t_events):
            return _history(times, states, burn_end, burn_end, earth)
        if burn_end >= horizon:  # still burning at the horizon
            return _history(times, states, burn_end, math.inf, earth)
        y0 = part.y[:, -1]
        step = float(part.t[-1] - part.t[-2]) if part.t.size > 1 else None
    if burn_end >= horizon:
        return _history(times, states, burn_end, math.inf, earth)
    second = _integrate(rates, (burn_end, horizon), y0, -1, math.inf, step)
    times.append(second.t)
    states.append(second.y)
    reentry = float(second.t[-1]) if _event_fired(second.t_events) else math.inf
    return _history(times, states, burn_end, reentry, earth)


@dataclass(frozen=True, eq=False)
class _AveragedRates:
    """d(a, e, m, J)/dt of the averaged orbit, and the events that end an integration."""

    drag_area_m2: float
    drag_coefficient: float
    density: DensityFunction
    earth: Earth
    cos_i: float
    burn: RetrogradeBurn | None

    def __call__(self, t: float, y: np.ndarray, segment: int) -> list[float]:
        """Rates with thrust segment ``segment`` firing (-1: none)."""
        earth, burn = self.earth, self.burn
        # Trial steps of the integrator may overshoot into nonsense: keep the orbit an orbit.
        a, e, m = max(y[0], earth.radius_m), min(max(y[1], 0.0), 0.9), y[2]
        area = self.drag_area_m2 if segment < 0 or burn is None else burn.drag_area_m2[segment]
        k = self.drag_coefficient * area / m
        da, de = _drag_rates(a, e, lambda h: self.density(h, t), k, earth, self.cos_i)
        if segment < 0 or burn is None:
            return [da, de, 0.0, 0.0]
        thrust = burn.thrust_N[segment]
        ta, te, duty = _thrust_rates(a, e, thrust / m, burn.half_width_rad, earth.mu_m3_s2)
        return [da + ta, de + te, -thrust * duty / burn.exhaust_speed_m_s, thrust * duty]

    def down(self, t: float, y: np.ndarray, *_: object) -> float:
        """Perigee radius less the re-entry radius: zero at re-entry."""
        reentry_radius = self.earth.radius_m + REENTRY_PERIGEE_KM * M_PER_KM
        return float(y[0] * (1.0 - max(y[1], 0.0)) - reentry_radius)


def _burn_stops(burn: RetrogradeBurn | None) -> list[tuple[int, float]]:
    """(segment, impulse at which it stops) of each segment the burn fires, in order."""
    if burn is None or burn.target_impulse_Ns <= 0.0:
        return []
    stops, start = [], 0.0
    for index, impulse in enumerate(burn.impulse_Ns):
        last = index == len(burn.impulse_Ns) - 1
        end = burn.target_impulse_Ns if last else min(start + impulse, burn.target_impulse_Ns)
        stops.append((index, end))
        start += impulse
        if end >= burn.target_impulse_Ns:
            break
    return stops


def _integrate(
    rates: _AveragedRates,
    span: tuple[float, float],
    y0: np.ndarray,
    segment: int,
    stop_Ns: float,
    first_step: float | None,
) -> Any:
    """RK45 from ``y0`` over ``span`` until re-entry, or until the impulse reaches
    ``stop_Ns`` when segment ``segment`` fires."""

    def down(t: float, y: np.ndarray, *_: object) -> float:
        return rates.down(t, y)

    def burnt(t: float, y: np.ndarray, *_: object) -> float:
        return float(y[3] - stop_Ns)

    down.terminal = True  # type: ignore[attr-defined]
    burnt.terminal = True  # type: ignore[attr-defined]
    return solve_ivp(
        rates,
        span,
        y0,
        args=(segment,),
        events=(down, burnt) if segment >= 0 else (down,),
        rtol=RTOL,
        atol=[1e-2, 1e-10, 1e-9, 1e-6],
        first_step=_first_step(first_step, span),
    )


def _first_step(step: float | None, span: tuple[float, float]) -> float | None:
    """The step to start with, within the span (None: let the integrator choose)."""
    if step is None or step <= 0.0:
        return None
    return min(step, 0.5 * (span[1] - span[0]))


def _event_fired(events: list[np.ndarray] | None) -> bool:
    """Whether the first event (re-entry) ended the integration."""
    return events is not None and bool(events[0].size)


def _history(
    times: list[np.ndarray],
    states: list[np.ndarray],
    burn_end: float,
    reentry: float,
    earth: Earth,
) -> DecayHistory:
    t = np.concatenate(times)
    y = np.concatenate(states, axis=1)
    return DecayHistory(
        time_s=t,
        semi_major_axis_m=y[0],
        eccentricity=np.maximum(y[1], 0.0),
        mass_kg=y[2],
        impulse_Ns=y[3],
        burn_end_s=burn_end,
        reentry_s=reentry,
        radius_m=earth.radius_m,
    )
