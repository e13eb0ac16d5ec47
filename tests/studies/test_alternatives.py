"""Swarm figures for design alternatives, against independent LPs on the engines."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from casadi_debris.allocation import Allocator
from casadi_debris.config import AXIS_NAMES, SIGNED_AXES, load_problem, signed_axis_vector
from casadi_debris.geometry import build_geometry, max_thrust_N, torque_authority
from casadi_debris.studies.alternatives import (
    failure_tolerance,
    fuel_per_torque,
    swarm_figures,
)
from lp_reference import ZERO_FORCE, largest_alpha, least_mass_flow_kg_s


def test_fuel_per_torque_is_the_least_mass_flow_of_an_independent_lp():
    problem = load_problem()
    geometry = build_geometry(problem)
    allocator = Allocator.from_problem(problem, geometry)
    authority = torque_authority(geometry, zero_net_force=True)
    rates = fuel_per_torque(allocator, authority)
    exhaust = np.array([e.isp_s for e in problem.engines]) * problem.constants.standard_gravity_m_s2
    for name in SIGNED_AXES:
        # A quarter of the authority: the least flow is linear in the torque below it.
        torque = 0.25 * authority[name] * signed_axis_vector(name)
        reference = least_mass_flow_kg_s(
            geometry, max_thrust_N(geometry), exhaust, torque, ZERO_FORCE
        )
        assert reference is not None
        assert rates[name] == pytest.approx(reference / (0.25 * authority[name]), rel=1e-7)


def test_the_paper_swarm_couples_need_the_analytic_flow_per_torque():
    """The paper's engines give pure torque in couples: two opposed engines of equal
    thrust T, torque T (b_i + b_j) for flow 2 T / c. The least flow per torque is that
    of the couple of largest torque, 2 / (c max (b_i + b_j)), over opposed pairs."""
    problem = load_problem()
    figures = swarm_figures(problem, max_failed=0)
    assert figures.problem_sha256 == problem.sha256 != ""
    geometry = build_geometry(problem)
    exhaust = problem.engine.isp_s * problem.constants.standard_gravity_m_s2
    directions = np.array([e.direction for e in geometry.engines])
    pairs = [
        (i, j)
        for i, j in itertools.permutations(range(len(directions)), 2)
        if np.allclose(directions[i], -directions[j])
    ]
    for axis in range(3):
        couple = max(geometry.torque_map[axis, [i, j]].sum() for i, j in pairs)
        expected = 2.0 / (exhaust * couple) * 1e3 * 3600 / 1e3  # g per mN m h
        name = f"+{AXIS_NAMES[axis]}"
        assert figures.fuel_per_torque_time_g_per_mNm_h[name] == pytest.approx(expected, rel=1e-9)
    assert figures.swarm_mass_kg == pytest.approx(24 * 3.5)
    assert figures.weakest_ratio == pytest.approx(
        figures.torque_max_zero_force_mNm[figures.weakest_axis] / 0.7, rel=1e-12
    )
    assert figures.single_failure is None and figures.double_failure is None


def test_failure_tolerance_matches_brute_force_with_an_independent_lp():
    problem = load_problem("two_per_face")
    geometry = build_geometry(problem)
    disturbance_Nm = np.abs(np.asarray(problem.disturbance.amplitude_mNm)) * 1e-3
    owner = geometry.engine_cubesat
    for size in (1, 2):
        found = failure_tolerance(geometry, disturbance_Nm, size)
        ratios = {}
        for failed in itertools.combinations(range(len(geometry.cubesats)), size):
            limits = np.where(np.isin(owner, failed), 0.0, max_thrust_N(geometry))
            ratios[failed] = min(
                largest_alpha(
                    geometry, limits, 1e-3 * signed_axis_vector(n), ZERO_FORCE, at_most=None
                )
                * 1e-3
                / disturbance_Nm[AXIS_NAMES.index(n[1])]
                for n in SIGNED_AXES
            )
        least = min(ratios.values())
        # Symmetric sets tie to round-off: the first of them in lexicographic order is reported.
        worst = next(s for s, r in ratios.items() if r <= least + 1e-6 * abs(least))
        assert found is not None and found.sets == len(ratios)
        assert found.worst_ratio == pytest.approx(least, rel=1e-6)
        assert found.failed == [k + 1 for k in worst]
        assert found.sets_above_disturbance == sum(r > 1.0 for r in ratios.values())
