"""The swarm's zero-torque thrust per direction and its staging, against independent solves."""

from __future__ import annotations

import itertools

import cvxpy as cp
import numpy as np
import pytest

from casadi_debris import load_problem
from casadi_debris.budgets import budgets_as_dict, compute_budgets
from casadi_debris.geometry import build_geometry, max_thrust_N
from casadi_debris.orbit.transfer_thrust import (
    burn_schedule,
    dv_of_burns,
    stage_switch_times_s,
    stage_use,
    thrust_groups,
)


@pytest.fixture(scope="module")
def paper():
    problem = load_problem()
    geometry = build_geometry(problem)
    return problem, geometry, thrust_groups(problem, geometry)


def test_each_direction_force_is_the_largest_balanced_push(paper) -> None:
    """The LP's force against cvxpy/Clarabel maximising the same push, stated per engine."""
    _, geometry, groups = paper
    limits = max_thrust_N(geometry)
    assert len(groups) == 6
    for group in groups:
        members = list(group.engines)
        f = cp.Variable(len(members))  # mN: well scaled for the interior-point solver
        lever = np.cross(
            np.array([geometry.engines[i].position_m for i in members]), group.direction
        )
        problem = cp.Problem(
            cp.Maximize(cp.sum(f)), [lever.T @ f == 0, f >= 0, f <= 1e3 * limits[members]]
        )
        problem.solve(solver=cp.CLARABEL)
        assert group.force_N * 1e3 == pytest.approx(problem.value, rel=1e-7)
        torque = geometry.torque_map @ group.thrust_N
        force = geometry.force_map @ group.thrust_N
        assert np.linalg.norm(torque) < 1e-12
        np.testing.assert_allclose(force, group.force_N * group.direction, atol=1e-12)
        # Four parallel engines: the net force is their sum, a little under 4 x 0.64 mN.
        assert 2.4e-3 < group.force_N <= 4 * 0.64e-3 + 1e-12


def test_staged_burns_give_the_budgets_all_faces_dv(paper) -> None:
    """All stages of all directions: within 2 % of the budget's rocket-equation 125 m/s.

    The budget fires every engine at full thrust; balancing the torque throttles
    some engines of each face (about 1 % less thrust).
    """
    problem, geometry, groups = paper
    burns = burn_schedule(groups)
    budget = budgets_as_dict(compute_budgets(problem, geometry))["dv_all_stages_all_faces_m_s"]
    dv = dv_of_burns(burns, geometry.mass_kg)
    assert dv[-1] == pytest.approx(budget, rel=0.02)
    assert dv[-1] < budget
    assert np.all(np.diff(dv) > 0)
    # Burns follow one another; each lasts its direction's three stages at 500 h.
    for before, after in itertools.pairwise(burns):
        assert after.start_s == pytest.approx(before.start_s + before.duration_s)
    assert all(b.duration_s == pytest.approx(1500 * 3600.0) for b in burns)


def test_extra_burns_cycle_through_the_directions(paper) -> None:
    _, _, groups = paper
    burns = burn_schedule(groups, extra=8)
    assert [b.real for b in burns] == [True] * 6 + [False] * 8
    assert [b.group for b in burns[6:]] == [0, 1, 2, 3, 4, 5, 0, 1]


def test_stage_use_and_switches_per_cubesat(paper) -> None:
    problem, geometry, groups = paper
    burns = burn_schedule(groups)
    uses = stage_use(problem, geometry, groups, {i: g.burn_time_s for i, g in enumerate(groups)})
    assert [u.cubesat for u in uses] == list(range(1, 25))
    assert all(u.stages == [1, 2, 3] for u in uses)
    # Propellant: the groups' flow over their burns, summed independently.
    total = sum(g.flow_kg_s * g.burn_time_s for g in groups)
    assert sum(u.propellant_kg for u in uses) == pytest.approx(total, rel=1e-12)
    # An engine at full thrust spends exactly 3 stages; a throttled one less.
    assert max(u.spent_stages for u in uses) == pytest.approx(3.0)
    switches = stage_switch_times_s(problem, geometry, groups, burns)
    assert switches == sorted(switches)
    assert {s[2] for s in switches} == {1, 2, 3}
    assert all(1 <= s[1] <= 24 for s in switches)


def test_a_throttled_stage_lasts_longer(paper) -> None:
    """At half throttle an engine at full thrust spends its first stage after 1000 h, not 500 h."""
    problem, geometry, groups = paper
    burns = burn_schedule(groups)
    end = burns[-1].start_s + burns[-1].duration_s
    half = stage_switch_times_s(
        problem, geometry, groups, burns, (np.array([0.0, end]), np.array([0.5]))
    )
    full = stage_switch_times_s(problem, geometry, groups, burns)
    first_half = min(t for t, _, stage in half if stage == 1)
    first_full = min(t for t, _, stage in full if stage == 1)
    assert first_full == pytest.approx(500 * 3600.0)
    assert first_half == pytest.approx(1000 * 3600.0)
    # Half throttle through a 1500 h burn: one stage and a half, so no third-stage switch.
    assert {stage for _, _, stage in half} == {1}
