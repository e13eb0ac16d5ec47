"""Lifetimes against an independent decay written here, with NRLMSIS called directly at each
orbit point's geodetic (WGS-84) latitude and altitude.

The independent model shares nothing with the library but the physics it states: its own
conversion to geodetic coordinates (the nearest point of the meridian ellipse, by Newton on
the parametric latitude), its own sampling of the orbit (argument of latitude over the whole
circle), of the day (8 local times) and its own NRLMSIS calls (one per point, fly-through),
and the circular decay as an integral over the semi-major axis (or a time integration when a
burn fires). Only the seasons sampled are the library's documented ones.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from casadi_debris.orbit import (
    REENTRY_PERIGEE_KM,
    SEASONS,
    SOLAR_CASES,
    Earth,
    SolarActivity,
    density_table,
    geodetic_from_geocentric,
    propagate_decay,
)
from casadi_debris.units import SECONDS_PER_YEAR

A_M = 6378137.0  # WGS-84 (NIMA TR8350.2), written again here
B_M = A_M * (1.0 - 1.0 / 298.257223563)
EARTH = Earth(mu_m3_s2=3.986004418e14, radius_m=A_M)
INCLINATION_DEG = 98.1
ORBIT_POINTS = 16
LOCAL_TIMES = 8
# Radial heights (r - a) the independent density is computed at [km]: finer where the
# scale height is short.
NODES_KM = np.concatenate([np.arange(100.0, 200.0, 10.0), np.arange(200.0, 720.0, 20.0)])


def geodetic(p_m: np.ndarray, z_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Geodetic latitude [rad] and height [m] of points (p, z) of a meridian plane: the
    nearest point (a cos t, b sin t) of the ellipse, by Newton on t."""
    t = np.arctan2(A_M * z_m, B_M * p_m)
    for _ in range(50):
        s, c = np.sin(t), np.cos(t)
        g = (A_M**2 - B_M**2) * s * c - A_M * p_m * s + B_M * z_m * c
        dg = (A_M**2 - B_M**2) * (c * c - s * s) - A_M * p_m * c - B_M * z_m * s
        step = g / dg
        t = t - step
        if np.all(np.abs(step) < 1e-15):
            break
    foot_p, foot_z = A_M * np.cos(t), B_M * np.sin(t)
    latitude = np.arctan2(A_M * np.sin(t), B_M * np.cos(t))
    return latitude, np.hypot(p_m - foot_p, z_m - foot_z)


def mean_density(heights_km: np.ndarray, activity: SolarActivity, *, spherical: bool = False):
    """Orbit-, day- and season-averaged NRLMSIS density at radii a + h [kg/m^3]; with
    ``spherical`` NRLMSIS is given h and the geocentric latitude instead (the old reading)."""
    from pymsis import msis

    u = (np.arange(ORBIT_POINTS) + 0.25) * 2.0 * math.pi / ORBIT_POINTS
    geocentric = np.arcsin(math.sin(math.radians(INCLINATION_DEG)) * np.sin(u))
    lons = (np.arange(LOCAL_TIMES) + 0.5) * 360.0 / LOCAL_TIMES
    dates = np.array(SEASONS, dtype="datetime64[m]")
    h, lat, lon, date = np.meshgrid(heights_km, geocentric, lons, dates, indexing="ij")
    radius = A_M + h * 1e3
    if spherical:
        latitude, height = lat, h * 1e3
    else:
        latitude, height = geodetic(radius * np.cos(lat), radius * np.sin(lat))
    n = h.size
    out = msis.calculate(
        date.ravel(),
        lon.ravel(),
        np.degrees(latitude).ravel(),
        height.ravel() / 1e3,
        f107s=np.full(n, activity.f107_sfu),
        f107as=np.full(n, activity.f107a_sfu),
        aps=np.full((n, 7), activity.ap),
        version=2.1,
    )
    return out[:, msis.Variable.MASS_DENSITY].reshape(h.shape).mean(axis=(1, 2, 3))


@dataclass(frozen=True)
class Atmosphere:
    """log rho on :data:`NODES_KM`, interpolated linearly (the test's own table)."""

    log_rho: np.ndarray

    @classmethod
    def of(cls, activity: SolarActivity, *, spherical: bool = False) -> Atmosphere:
        return cls(np.log(mean_density(NODES_KM, activity, spherical=spherical)))

    def __call__(self, height_m: float) -> float:
        return float(np.exp(np.interp(height_m / 1e3, NODES_KM, self.log_rho)))


def _drag_da_dt(a: float, rho: float, k: float) -> float:
    """Circular orbit, drag of the air turning with the Earth: -rho k (w/v)^2 sqrt(mu a)."""
    v = math.sqrt(EARTH.mu_m3_s2 / a)
    w = v - EARTH.rotation_rad_s * a * math.cos(math.radians(INCLINATION_DEG))
    return -rho * k * (w / v) ** 2 * math.sqrt(EARTH.mu_m3_s2 * a)


def lifetime_years(atmosphere: Atmosphere, altitude_km: float, k_m2_kg: float) -> float:
    """Circular decay from ``altitude_km`` to the re-entry height: t = int da / |da/dt|."""
    low = EARTH.radius_m + REENTRY_PERIGEE_KM * 1e3
    high = EARTH.radius_m + altitude_km * 1e3
    breaks = [EARTH.radius_m + x * 1e3 for x in NODES_KM if low < EARTH.radius_m + x * 1e3 < high]
    seconds, _ = quad(
        lambda a: -1.0 / _drag_da_dt(a, atmosphere(a - EARTH.radius_m), k_m2_kg),
        low,
        high,
        points=breaks,
        limit=400,
        epsrel=1e-8,
    )
    return seconds / SECONDS_PER_YEAR


@dataclass(frozen=True)
class Spiral:
    """A retrograde burn all the orbit round, thrust segment after segment, then decay."""

    thrust_N: tuple[float, ...]
    impulse_Ns: tuple[float, ...]
    burn_area_m2: tuple[float, ...]
    decay_area_m2: float
    drag_coefficient: float
    mass_kg: float
    exhaust_speed_m_s: float

    def reentry_years(self, atmosphere: Atmosphere, altitude_km: float, dv_m_s: float) -> float:
        """Years from the burn's start to re-entry (inf past 200 years)."""
        ve = self.exhaust_speed_m_s
        target = self.mass_kg * ve * (1.0 - math.exp(-dv_m_s / ve))
        floor = EARTH.radius_m + REENTRY_PERIGEE_KM * 1e3
        t, state = 0.0, np.array([EARTH.radius_m + altitude_km * 1e3, self.mass_kg])
        given = 0.0
        arcs = []
        for thrust, impulse, area in zip(
            self.thrust_N, self.impulse_Ns, self.burn_area_m2, strict=True
        ):
            part = min(impulse, target - given)
            if part <= 0.0:
                break
            arcs.append((thrust, area, part / thrust))
            given += part
        arcs.append((0.0, self.decay_area_m2, 200.0 * SECONDS_PER_YEAR))

        def down(_t: float, y: np.ndarray, *_: object) -> float:
            return y[0] - floor

        down.terminal = True  # type: ignore[attr-defined]
        for thrust, area, duration in arcs:

            def rates(_t: float, y: np.ndarray, thrust=thrust, area=area) -> list[float]:
                a, m = y
                k = self.drag_coefficient * area / m
                push = -2.0 * thrust / m * a**1.5 / math.sqrt(EARTH.mu_m3_s2)
                da = _drag_da_dt(a, atmosphere(a - EARTH.radius_m), k) + push
                return [da, -thrust / ve]

            sol = solve_ivp(
                rates, (t, t + duration), state, events=down, rtol=1e-9, atol=[1e-3, 1e-9]
            )
            if sol.t_events[0].size:
                return float(sol.t_events[0][0]) / SECONDS_PER_YEAR
            t, state = float(sol.t[-1]), sol.y[:, -1]
        return math.inf


@pytest.fixture(scope="module")
def atmospheres() -> dict[str, Atmosphere]:
    return {name: Atmosphere.of(case) for name, case in SOLAR_CASES.items()}


def test_the_geodetic_conversion_agrees_with_the_nearest_point_of_the_ellipse() -> None:
    rng = np.random.default_rng(20261127)
    radius = A_M + rng.uniform(100e3, 2000e3, 500)
    latitude = rng.uniform(-math.pi / 2, math.pi / 2, 500)
    got_lat, got_h = geodetic_from_geocentric(radius, latitude)
    want_lat, want_h = geodetic(radius * np.cos(latitude), radius * np.sin(latitude))
    np.testing.assert_allclose(got_lat, want_lat, rtol=0, atol=1e-11)
    np.testing.assert_allclose(got_h, want_h, rtol=0, atol=1e-5)
    # Over a pole the height is the distance to the polar radius; over the equator, to a.
    _, pole = geodetic_from_geocentric(A_M + 685e3, math.pi / 2)
    _, equator = geodetic_from_geocentric(A_M + 685e3, 0.0)
    assert float(pole) == pytest.approx(685e3 + A_M - B_M, abs=1e-6)
    assert float(equator) == pytest.approx(685e3, abs=1e-6)


@pytest.mark.parametrize(
    ("solar", "altitude_km"), [("low", 450.0), ("mean", 685.0), ("high", 685.0)]
)
def test_the_decay_matches_an_independent_one_with_nrlmsis_called_directly(
    atmospheres: dict[str, Atmosphere], solar: str, altitude_km: float
) -> None:
    """The paper's debris tumbling (668 kg, 8 m^2, C_D 2.2) from a circular orbit."""
    k = 2.2 * 8.0 / 668.0
    table = density_table(INCLINATION_DEG)
    f107 = SOLAR_CASES[solar].f107_sfu
    history = propagate_decay(
        EARTH.radius_m + altitude_km * 1e3,
        0.0,
        668.0,
        drag_area_m2=8.0,
        drag_coefficient=2.2,
        density=lambda h, t: table.density(h, f107),
        earth=EARTH,
        inclination_rad=math.radians(INCLINATION_DEG),
    )
    expected = lifetime_years(atmospheres[solar], altitude_km, k)
    assert history.reentry_years == pytest.approx(expected, rel=5e-3)
    # The spherical reading (height r - a, geocentric latitude) lives 11-23 % shorter.
    spherical = lifetime_years(Atmosphere.of(SOLAR_CASES[solar], spherical=True), altitude_km, k)
    assert expected / spherical > 1.1
