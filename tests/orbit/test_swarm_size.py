"""The smallest swarm: it meets the limit, one CubeSat fewer does not."""

from __future__ import annotations

import math

import pytest

from casadi_debris.orbit import (
    DeorbitModel,
    DeorbitSettings,
    best_strategy,
    minimum_swarm,
    solar_case,
    swarm_of,
)

MEAN_SPIRAL = DeorbitSettings(solar=("mean",), strategies=("spiral",), minimum_swarm=False)


def test_one_cubesat_fewer_does_not_carry_the_needed_dv(problem) -> None:
    model = DeorbitModel.from_problem(problem, MEAN_SPIRAL)
    smallest = minimum_swarm(model, MEAN_SPIRAL, "mean")
    assert smallest is not None
    n = smallest.cubesats
    # What n CubeSats of 3.5 kg, 3 stages of 0.64 mN x 500 h, Isp 1000 s carry (by hand).
    bare = 668.0 - 24 * 3.5
    propellant = 3 * 0.64e-3 * 500 * 3600 / (1000 * 9.80665)

    def carried(count: int) -> float:
        mass = bare + count * 3.5
        return 1000 * 9.80665 * math.log(mass / (mass - count * propellant))

    assert smallest.capacity_dv_m_s == pytest.approx(carried(n))
    assert smallest.deorbit_dv_m_s <= carried(n)
    fewer = swarm_of(model, n - 1)
    need, _ = best_strategy(fewer, fewer.density(solar_case("mean")), MEAN_SPIRAL)
    assert need > carried(n - 1)
    assert smallest.thrust_mN == pytest.approx(0.64 * n)
