"""Edelbaum steering in closed loop against the analytic transfers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from casadi_debris.orbit import EARTH_J2, mee_circular
from casadi_debris.orbit.transfer import (
    Burn,
    averaged_dynamics,
    edelbaum_guidance,
    radius_inclination,
)

MU = 3.986004418e14
RE = 6378137.0
EXHAUST = 1000.0 * 9.80665


def _burns(force_N: float, days: float, count: int = 1) -> list[Burn]:
    length = days * 86400.0
    return [Burn(0, i * length, length, force_N, force_N / EXHAUST, True) for i in range(count)]


def _dv(mass: np.ndarray) -> float:
    return EXHAUST * math.log(mass[0] / mass[-1])


def test_coplanar_spiral_costs_the_circular_speed_difference() -> None:
    """No plane change, no J2: the low-thrust spiral's dv is |V0 - V1| (Edelbaum with di = 0)."""
    r0, r1 = RE + 550e3, RE + 685e3
    run = edelbaum_guidance(
        averaged_dynamics(),
        mee_circular(r0, math.radians(97.5)),
        668.0,
        (r1, math.radians(97.5)),
        _burns(0.05, 30.0),
        (MU, RE, 0.0),
    )
    assert run.reached
    assert _dv(run.mass_kg) == pytest.approx(math.sqrt(MU / r0) - math.sqrt(MU / r1), rel=1e-4)


def test_paper_transfer_with_j2_matches_edelbaum_and_reaches_the_target() -> None:
    """550 km / 97.5 deg -> 685 km / 98.1 deg: Edelbaum's dv, inline, within 0.5 %."""
    r0, r1 = RE + 550e3, RE + 685e3
    di = math.radians(0.6)
    v0, v1 = math.sqrt(MU / r0), math.sqrt(MU / r1)
    edelbaum = math.sqrt(v0**2 - 2 * v0 * v1 * math.cos(math.pi / 2 * di) + v1**2)
    run = edelbaum_guidance(
        averaged_dynamics(),
        mee_circular(r0, math.radians(97.5)),
        668.0,
        (r1, math.radians(98.1)),
        _burns(0.02, 40.0, count=3),
        (MU, RE, EARTH_J2),
    )
    assert run.reached and run.remaining_dv_m_s < 1e-3
    assert _dv(run.mass_kg) == pytest.approx(edelbaum, rel=5e-3)
    radius, inclination = radius_inclination(run.elements[-1])
    assert radius == pytest.approx(r1, abs=50.0)
    assert inclination == pytest.approx(math.radians(98.1), abs=1e-5)
    assert np.all(np.diff(run.time_s) > 0)


def test_stops_when_the_burns_run_out() -> None:
    run = edelbaum_guidance(
        averaged_dynamics(),
        mee_circular(RE + 550e3, math.radians(97.5)),
        668.0,
        (RE + 685e3, math.radians(98.1)),
        _burns(0.0025, 10.0),
        (MU, RE, EARTH_J2),
    )
    assert not run.reached
    assert run.time_s[-1] == pytest.approx(10 * 86400.0)
    assert run.remaining_dv_m_s > 100.0
