"""The averaged decay against closed forms, a Cartesian integration and monotonicity."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from casadi_debris.orbit import (
    REENTRY_PERIGEE_KM,
    SOLAR_CASES,
    Earth,
    RetrogradeBurn,
    density_table,
    propagate_decay,
)
from casadi_debris.units import SECONDS_PER_YEAR

EARTH = Earth(mu_m3_s2=3.986004418e14, radius_m=6378137.0)
STILL_EARTH = Earth(mu_m3_s2=3.986004418e14, radius_m=6378137.0, rotation_rad_s=0.0)
INCLINATION = math.radians(98.1)


@pytest.fixture(scope="module")
def table():
    return density_table(98.1)


def test_circular_decay_in_an_exponential_atmosphere_matches_quadrature() -> None:
    # da/dt = -sqrt(mu a) rho0 exp(-(h - h0)/H) C_D A / m: time to fall is an integral.
    rho0, h0, scale = 1e-13, 500e3, 60e3
    k = 2.2 * 4.0 / 500.0

    def density(h: np.ndarray, t: float) -> np.ndarray:
        return rho0 * np.exp(-(h - h0) / scale)

    a0 = EARTH.radius_m + 500e3
    af = EARTH.radius_m + REENTRY_PERIGEE_KM * 1e3
    exact, _ = quad(
        lambda a: 1.0 / (math.sqrt(EARTH.mu_m3_s2 * a) * k * density(a - EARTH.radius_m, 0.0)),
        af,
        a0,
        limit=200,
    )
    history = propagate_decay(
        a0,
        0.0,
        500.0,
        drag_area_m2=4.0,
        drag_coefficient=2.2,
        density=density,
        earth=STILL_EARTH,
        inclination_rad=INCLINATION,
    )
    assert history.reentry_s == pytest.approx(exact, rel=1e-4)


def _cartesian(state0, days, density, k, earth):
    """Two-body motion with drag relative to the turning atmosphere, in inertial axes."""
    spin = np.array([0.0, 0.0, earth.rotation_rad_s])

    def rhs(t, y):
        r, v = y[:3], y[3:]
        radius = np.linalg.norm(r)
        relative = v - np.cross(spin, r)
        rho = float(density(np.array(radius - earth.radius_m), t))
        drag = -0.5 * k * rho * np.linalg.norm(relative) * relative
        return np.concatenate([v, -earth.mu_m3_s2 * r / radius**3 + drag])

    sol = solve_ivp(rhs, (0.0, days * 86400.0), state0, method="DOP853", rtol=1e-11, atol=1e-6)
    r, v = sol.y[:3, -1], sol.y[3:, -1]
    energy = 0.5 * v @ v - earth.mu_m3_s2 / np.linalg.norm(r)
    a = -earth.mu_m3_s2 / (2.0 * energy)
    h = np.cross(r, v)
    e = np.linalg.norm(np.cross(v, h) / earth.mu_m3_s2 - r / np.linalg.norm(r))
    return a, e


def _initial_state(a, e, earth):
    """At perigee, in an orbit inclined by 98.1 deg."""
    rp = a * (1.0 - e)
    vp = math.sqrt(earth.mu_m3_s2 * (1.0 + e) / rp)
    c, s = math.cos(INCLINATION), math.sin(INCLINATION)
    return np.array([rp, 0.0, 0.0, 0.0, vp * c, vp * s])


@pytest.mark.parametrize(
    ("perigee_km", "apogee_km", "days"), [(300.0, 300.0, 3.0), (250.0, 600.0, 2.5)]
)
def test_averaged_decay_matches_a_cartesian_integration(table, perigee_km, apogee_km, days) -> None:
    f107 = SOLAR_CASES["mean"].f107_sfu

    def density(h, t):
        return table.density(h, f107)

    rp, ra = EARTH.radius_m + perigee_km * 1e3, EARTH.radius_m + apogee_km * 1e3
    a0, e0 = 0.5 * (rp + ra), (ra - rp) / (ra + rp)
    area, cd, mass = 1.0, 2.2, 50.0
    a_ref, e_ref = _cartesian(_initial_state(a0, e0, EARTH), days, density, cd * area / mass, EARTH)
    history = propagate_decay(
        a0,
        e0,
        mass,
        drag_area_m2=area,
        drag_coefficient=cd,
        density=density,
        earth=EARTH,
        inclination_rad=INCLINATION,
        horizon_years=days / 365.25,
    )
    drop = a0 - history.semi_major_axis_m[-1]
    assert drop > 5e3  # a real decay, kilometres
    assert drop == pytest.approx(a0 - a_ref, rel=0.01)
    if e0 > 0:
        assert e0 - history.eccentricity[-1] == pytest.approx(e0 - e_ref, rel=0.02)


def _lifetime(table, f107, area_m2, altitude_km=450.0):
    history = propagate_decay(
        EARTH.radius_m + altitude_km * 1e3,
        0.0,
        100.0,
        drag_area_m2=area_m2,
        drag_coefficient=2.2,
        density=lambda h, t: table.density(h, f107),
        earth=EARTH,
        inclination_rad=INCLINATION,
    )
    return history.reentry_years


def test_lifetime_falls_with_area_to_mass_and_solar_flux(table) -> None:
    by_area = [_lifetime(table, 140.0, area) for area in (0.5, 1.0, 2.0, 4.0)]
    assert all(x > y for x, y in itertools.pairwise(by_area))
    # Lifetime goes nearly as 1 / (area-to-mass): doubling the area roughly halves it.
    assert by_area[0] / by_area[1] == pytest.approx(2.0, rel=0.1)
    by_flux = [_lifetime(table, f, 1.0) for f in (65.0, 100.0, 140.0, 200.0, 250.0)]
    assert all(x > y for x, y in itertools.pairwise(by_flux))


def _burn(target_Ns, thrust_N=0.01, half_width=math.pi):
    return RetrogradeBurn(
        thrust_N=(thrust_N,),
        impulse_Ns=(1e9,),
        target_impulse_Ns=target_Ns,
        exhaust_speed_m_s=1000.0 * 9.80665,
        drag_area_m2=(0.0,),
        half_width_rad=half_width,
    )


def _vacuum(h, t):
    return np.zeros_like(np.asarray(h, dtype=float))


def test_a_circular_spiral_gains_the_rocket_equation_speed() -> None:
    # Continuous tangential thrust on a circular orbit: dv = v(a1) - v(a0) exactly.
    mass, ve, target = 500.0, 1000.0 * 9.80665, 20000.0
    a0 = EARTH.radius_m + 700e3
    history = propagate_decay(
        a0,
        0.0,
        mass,
        drag_area_m2=0.0,
        drag_coefficient=2.2,
        density=_vacuum,
        earth=EARTH,
        inclination_rad=INCLINATION,
        burn=_burn(target),
        horizon_years=5.0,
    )
    end = int(np.searchsorted(history.time_s, history.burn_end_s))
    a1 = history.semi_major_axis_m[end]
    dv_orbit = math.sqrt(EARTH.mu_m3_s2 / a1) - math.sqrt(EARTH.mu_m3_s2 / a0)
    dv_rocket = ve * math.log(mass / (mass - target / ve))
    assert dv_orbit == pytest.approx(dv_rocket, rel=1e-5)
    assert history.eccentricity[end] < 1e-9
    assert history.mass_kg[end] == pytest.approx(mass - target / ve, rel=1e-9)


def test_short_arcs_at_apogee_act_as_an_impulse() -> None:
    # A retrograde kick dv at apogee of a circle of radius r: new perigee from vis-viva.
    mass, target = 500.0, 5000.0
    ve = 1000.0 * 9.80665
    r = EARTH.radius_m + 700e3
    history = propagate_decay(
        r,
        0.0,
        mass,
        drag_area_m2=0.0,
        drag_coefficient=2.2,
        density=_vacuum,
        earth=EARTH,
        inclination_rad=INCLINATION,
        burn=_burn(target, half_width=math.radians(5.0)),
        horizon_years=20.0,
    )
    end = int(np.searchsorted(history.time_s, history.burn_end_s))
    dv = ve * math.log(mass / (mass - target / ve))
    v_apogee = math.sqrt(EARTH.mu_m3_s2 / r) - dv
    a_impulsive = 1.0 / (2.0 / r - v_apogee**2 / EARTH.mu_m3_s2)
    perigee_impulsive = 2.0 * a_impulsive - r
    assert history.perigee_altitude_m[end] + EARTH.radius_m == pytest.approx(
        perigee_impulsive, abs=200.0
    )
    assert history.apogee_altitude_m[end] + EARTH.radius_m == pytest.approx(r, abs=200.0)


def test_lifetime_beyond_the_horizon_is_infinite(table) -> None:
    history = propagate_decay(
        EARTH.radius_m + 1200e3,
        0.0,
        1000.0,
        drag_area_m2=1.0,
        drag_coefficient=2.2,
        density=lambda h, t: table.density(h, 65.0),
        earth=EARTH,
        inclination_rad=INCLINATION,
        horizon_years=10.0,
    )
    assert math.isinf(history.reentry_years)
    assert history.time_s[-1] == pytest.approx(10.0 * SECONDS_PER_YEAR)


@pytest.mark.parametrize("margin_s", [-1e5, 10.0])
def test_a_burn_ending_at_or_past_the_horizon_is_no_error(margin_s) -> None:
    # In vacuum the burn lasts target / thrust; the horizon falls just before or after it.
    burn = _burn(20000.0)
    duration = 20000.0 / 0.01
    history = propagate_decay(
        EARTH.radius_m + 700e3,
        0.0,
        500.0,
        drag_area_m2=0.0,
        drag_coefficient=2.2,
        density=_vacuum,
        earth=EARTH,
        inclination_rad=INCLINATION,
        burn=burn,
        horizon_years=(duration + margin_s) / SECONDS_PER_YEAR,
    )
    assert math.isinf(history.reentry_years)
    assert history.time_s[-1] == pytest.approx(duration + margin_s, rel=1e-6)
