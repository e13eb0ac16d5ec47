"""The closed-loop detumble against exact answers: a body whose momentum keeps its direction,
the energy the torque removes, the propellant of the thrust, and the momentum bound."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import linprog

from casadi_debris import load_problem
from casadi_debris.allocation import Allocator
from casadi_debris.errors import CasadiDebrisError
from casadi_debris.geometry import build_geometry
from casadi_debris.simulation.detumble import simulate_detumble
from casadi_debris.workflows import momentum_bound_s

GAIN, PERIOD = 0.02, 1.0


@pytest.fixture(scope="module")
def problem():
    return load_problem()


@pytest.fixture(scope="module")
def geometry(problem):
    return build_geometry(problem)


def _fastest_brake_Nm(geometry, direction: np.ndarray) -> float:
    """max over thrusts of -d . (B f) at zero net force: an LP of its own."""
    f_max = np.array([e.max_thrust_N for e in geometry.engines])
    found = linprog(
        direction @ geometry.torque_map,
        A_eq=geometry.force_map,
        b_eq=np.zeros(3),
        bounds=list(zip(np.zeros_like(f_max), f_max, strict=True)),
        method="highs",
    )
    return -float(found.fun)


def test_each_saturated_step_brakes_the_momentum_as_fast_as_any_thrust_can(
    problem, geometry, tumble
) -> None:
    """-H . tau / |H| against an LP over the thrusts at zero net force, step by step."""
    momentum = tumble.rate_rad_s[:-1] @ geometry.inertia_total_kgm2.T
    saturated = np.flatnonzero(tumble.scale < 1.0)
    assert len(saturated) > 100
    for k in saturated[:: len(saturated) // 40]:
        direction = momentum[k] / np.linalg.norm(momentum[k])
        brake = -direction @ tumble.torque_Nm[k]
        assert brake == pytest.approx(_fastest_brake_Nm(geometry, direction), rel=1e-9)


def test_once_the_engines_can_the_damping_is_linear(geometry, tumble) -> None:
    linear = np.flatnonzero(tumble.scale >= 1.0)
    assert len(linear) > 10
    momentum = tumble.rate_rad_s[linear] @ geometry.inertia_total_kgm2.T
    np.testing.assert_allclose(tumble.torque_Nm[linear], -GAIN * momentum, rtol=1e-12)


@pytest.fixture(scope="module")
def tumble(problem):
    return simulate_detumble(problem, initial_rate_rad_s=[0.02, 0.03, -0.02], threshold_rad_s=1e-4)


def test_the_torque_removes_the_kinetic_energy(problem, geometry, tumble) -> None:
    inertia = geometry.inertia_total_kgm2
    rates, torque = tumble.rate_rad_s, tumble.torque_Nm
    energy0 = 0.5 * rates[0] @ inertia @ rates[0]
    # dE/dt = omega . tau; the rate within a period from its two ends.
    work = np.sum(np.einsum("ij,ij->i", 0.5 * (rates[:-1] + rates[1:]), torque)) * PERIOD
    final = 0.5 * rates[-1] @ inertia @ rates[-1]
    assert final - energy0 == pytest.approx(work, rel=2e-3)


def test_the_propellant_is_that_of_the_least_fuel_thrust(problem, geometry, tumble) -> None:
    thrust = Allocator.from_problem(problem, geometry).allocate_series(tumble.torque_Nm).thrust_N
    c = 1000.0 * 9.80665  # the paper's Isp
    assert tumble.summary.fuel_kg == pytest.approx(thrust.sum() * PERIOD / c, rel=1e-6)
    assert tumble.fuel_per_cubesat_kg[-1].sum() == pytest.approx(tumble.summary.fuel_kg)


def test_no_detumble_beats_the_momentum_bound(problem, tumble) -> None:
    assert tumble.summary.time_to_threshold_s >= momentum_bound_s(problem, tumble.rate_rad_s[0])


@pytest.mark.parametrize(
    ("options", "field"),
    [
        ({"gain_per_s": 2.0}, "gain_per_s"),
        ({"threshold_rad_s": 0.0}, "threshold_rad_s"),
        ({"initial_rate_rad_s": [1.0, np.nan, 0.0]}, "initial_rate_rad_s"),
    ],
)
def test_bad_settings_name_the_field(problem, options, field) -> None:
    with pytest.raises(CasadiDebrisError, match=field):
        simulate_detumble(problem, **options)
