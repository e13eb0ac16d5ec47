"""The averaged NRLMSIS density table against direct NRLMSIS calls, offline."""

from __future__ import annotations

import math
import socket

import numpy as np
import pytest

from casadi_debris.errors import InputShapeError
from casadi_debris.orbit import (
    SOLAR_CASES,
    density_table,
    msis_mean_density,
    solar_case,
)
from tests.orbit.test_lifetime_msis import A_M, geodetic

INCLINATION_DEG = 98.1


@pytest.fixture(scope="module")
def table():
    return density_table(INCLINATION_DEG)


def test_the_table_is_the_mean_over_randomly_sampled_orbit_points(table) -> None:
    # An independent average: NRLMSIS at random dates of a year, random UT and
    # longitudes, and argument of latitude uniform over the orbit (fly-through mode),
    # each point of the circle of radius a + 500 km placed on WGS-84 by the test's own
    # conversion (the nearest point of the meridian ellipse).
    from pymsis import msis

    rng = np.random.default_rng(7)
    n = 6000
    start = np.datetime64("2020-01-01T00:00", "m")
    dates = start + rng.integers(0, 366 * 24 * 60, n).astype("timedelta64[m]")
    u = rng.uniform(0.0, 2.0 * math.pi, n)
    geocentric = np.arcsin(math.sin(math.radians(INCLINATION_DEG)) * np.sin(u))
    radius = A_M + 500e3
    lats, heights = geodetic(radius * np.cos(geocentric), radius * np.sin(geocentric))
    lons = rng.uniform(0.0, 360.0, n)
    case = SOLAR_CASES["mean"]
    out = msis.calculate(
        dates,
        lons,
        np.degrees(lats),
        heights / 1e3,
        f107s=np.full(n, case.f107_sfu),
        f107as=np.full(n, case.f107a_sfu),
        aps=np.full((n, 7), case.ap),
    )
    sampled = out[:, msis.Variable.MASS_DENSITY]
    standard_error = sampled.std() / math.sqrt(n)
    table_value = float(table.density(500e3, case.f107_sfu))
    assert abs(sampled.mean() - table_value) < max(4.0 * standard_error, 0.03 * table_value)


def test_log_interpolation_between_nodes_is_within_half_a_percent(table) -> None:
    for altitude_km in (205.0, 455.0, 685.0, 1234.0):
        direct = msis_mean_density(np.array([altitude_km]), SOLAR_CASES["low"], INCLINATION_DEG)
        read = table.density(altitude_km * 1e3, SOLAR_CASES["low"].f107_sfu)
        assert read == pytest.approx(direct[0], rel=5e-3)


def test_density_falls_with_altitude_and_rises_with_solar_flux(table) -> None:
    altitudes = np.linspace(120e3, 1500e3, 50)
    for case in SOLAR_CASES.values():
        assert np.all(np.diff(table.density(altitudes, case.f107_sfu)) < 0.0)
    at_685 = [float(table.density(685e3, c.f107_sfu)) for c in SOLAR_CASES.values()]
    assert at_685[0] < at_685[1] < at_685[2]
    # Solar activity moves the density at 685 km by well over an order of magnitude.
    assert at_685[2] / at_685[0] > 30.0


def test_the_named_cases_are_read_exactly_at_their_level(table) -> None:
    altitudes = np.array([300.0, 680.0])  # nodes of the altitude grid
    for case in SOLAR_CASES.values():
        direct = msis_mean_density(altitudes, case, INCLINATION_DEG)
        np.testing.assert_allclose(table.density(altitudes * 1e3, case.f107_sfu), direct, rtol=1e-9)


def test_no_network_is_touched(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(*args: object, **kwargs: object) -> None:
        raise OSError("network access in a test")

    monkeypatch.setattr(socket, "socket", refuse)
    density = msis_mean_density(np.array([400.0]), SOLAR_CASES["high"], 51.6)
    assert np.isfinite(density).all() and density[0] > 0.0


def test_an_unknown_case_names_the_field() -> None:
    with pytest.raises(InputShapeError, match="solar activity"):
        solar_case("extreme")
