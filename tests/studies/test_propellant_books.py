"""The propellant books against hand sums, and the swarm's leftover thrust against the LP's
linearity."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from casadi_debris.config import load_problem
from casadi_debris.errors import AllocationError
from casadi_debris.geometry import build_geometry
from casadi_debris.orbit import swarm_thrust
from casadi_debris.simulation.detumble import simulate_detumble
from casadi_debris.studies.mission import thrust_left, transfer_per_engine
from casadi_debris.studies.propellant_books import PropellantBooks, detumble_engine_kg


def small_books() -> PropellantBooks:
    """Two CubeSats: CubeSat 1 with engines 1 (two stages of 10 g) and 2 (one of 5 g),
    CubeSat 2 with engine 3 (two stages of 8 g)."""
    capacity = np.array([[0.010, 0.010], [0.005, 0.0], [0.008, 0.008]])
    return PropellantBooks(
        capacity_kg=capacity,
        used_kg=np.zeros_like(capacity),
        exhaust_m_s=np.full(3, 9806.65),
        engine_cubesat=np.array([0, 0, 1]),
    )


def test_stages_are_drawn_in_order_and_summed_per_cubesat():
    books = small_books()
    first = books.burn("a", np.array([0.004, 0.005, 0.0]))
    assert first.per_cubesat_kg == pytest.approx([0.009, 0.0])
    np.testing.assert_allclose(first.per_stage_kg, [[0.009, 0.0], [0.0, 0.0]], atol=1e-15)
    assert first.stages_started == [[1], []]
    second = books.burn("b", np.array([0.012, 0.0, 0.0105]))
    # engine 1: 6 g left in stage 1, then 6 g of stage 2; engine 3: 8 g then 2.5 g
    np.testing.assert_allclose(second.per_stage_kg, [[0.006, 0.006], [0.008, 0.0025]], atol=1e-15)
    assert second.stages_started == [[1, 2], [1, 2]]
    assert second.left_per_cubesat_kg == pytest.approx([0.004, 0.0055])
    assert second.propellant_kg == pytest.approx(0.0225)
    assert np.all(books.used_kg <= books.capacity_kg + 1e-15)


def test_an_engine_cannot_burn_more_than_it_carries():
    books = small_books()
    books.burn("a", np.array([0.0, 0.004, 0.0]))
    with pytest.raises(AllocationError, match=r"engine 2 \(CubeSat 1\)"):
        books.burn("b", np.array([0.0, 0.002, 0.0]))
    assert books.used_kg.sum() == pytest.approx(0.004)  # the refused phase took nothing


def test_full_books_match_the_problem_and_the_transfer_uses_each_strongest_engine():
    problem = load_problem()
    books = PropellantBooks.from_problem(problem)
    g0 = problem.constants.standard_gravity_m_s2
    by_hand = sum(e.stages * e.thrust_per_stage_mN * 1e-3 * e.stage_life_h * 3600 / (e.isp_s * g0)
                  for e in problem.engines)  # fmt: skip
    assert books.capacity_kg.sum() == pytest.approx(by_hand, rel=1e-12)
    dv, engine_kg, _ = transfer_per_engine(problem)
    page = books.burn("transfer", engine_kg)
    assert page.stages_started == [[1]] * len(problem.cubesats)  # half a stage each
    assert page.propellant_kg == pytest.approx(
        sum(c.mass_kg * (1 - np.exp(-dv / (1000.0 * g0))) for c in problem.cubesats), rel=1e-12
    )


def test_leftover_thrust_scales_with_the_leftovers():
    """The LP is homogeneous in the capacities: half of every engine's impulse gives half the
    torque-free impulse at the same thrusts; all of it gives swarm_thrust's own answer."""
    problem = load_problem()
    geometry = build_geometry(problem)
    full = swarm_thrust(problem, geometry)
    same = thrust_left(problem, geometry, full.engine_capacity_Ns, full)
    assert same.impulse_Ns == pytest.approx(full.impulse_Ns, rel=1e-9)
    half = thrust_left(problem, geometry, 0.5 * full.engine_capacity_Ns, full)
    assert half.impulse_Ns == pytest.approx(0.5 * full.impulse_Ns, rel=1e-9)
    np.testing.assert_allclose(
        [s.thrust_N for s in half.segments], [s.thrust_N for s in full.segments], rtol=1e-9
    )
    np.testing.assert_allclose(half.stage_impulse_Ns, full.stage_impulse_Ns)
    # An empty engine: no mix uses it, and nothing else goes over what it has.
    left = full.engine_capacity_Ns.copy()
    left[0] = 0.0
    lame = thrust_left(problem, geometry, left, full)
    used = lame.engine_impulse(lame.impulse_Ns)
    assert used[0] == pytest.approx(0.0, abs=1e-6)
    assert np.all(used <= left * (1 + 1e-9) + 1e-6)
    assert lame.impulse_Ns < full.impulse_Ns


@pytest.mark.slow
def test_the_detumble_replay_splits_the_runs_fuel_among_the_engines():
    """Five engines per CubeSat: the replay through the allocator and staging gives back the
    run's fuel per CubeSat, and only engines that can push fire."""
    problem = load_problem(Path(__file__).parents[2] / "problems/gallery/side_engines_12.toml")
    run = simulate_detumble(problem)
    engine_kg = detumble_engine_kg(problem, run)
    assert engine_kg.shape == (len(problem.engines),)
    assert np.all(engine_kg >= 0.0)
    per_cubesat = np.bincount(problem.engine_cubesats, weights=engine_kg)
    np.testing.assert_allclose(per_cubesat, run.summary.fuel_per_cubesat_kg, rtol=1e-9, atol=1e-12)
    assert np.count_nonzero(engine_kg) > len(problem.cubesats)  # more than one engine each
