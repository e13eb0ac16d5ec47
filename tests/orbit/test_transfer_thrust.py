"""Transfer burns from the swarm's thrust segments, and their staging, checked independently."""

from __future__ import annotations

import itertools

import cvxpy as cp
import numpy as np
import pytest

from casadi_debris import load_problem
from casadi_debris.budgets import budgets_as_dict, compute_budgets
from casadi_debris.geometry import build_geometry, max_thrust_N
from casadi_debris.orbit import swarm_thrust
from casadi_debris.orbit.transfer import (
    burn_schedule,
    dv_of_burns,
    stage_switch_times_s,
    stage_use,
)

HOUR = 3600.0


@pytest.fixture(scope="module")
def paper():
    problem = load_problem()
    geometry = build_geometry(problem)
    return problem, geometry, swarm_thrust(problem, geometry).segments


def _own_engines_push_N(geometry, direction: np.ndarray) -> float:
    """The largest push of the engines along ``direction`` alone at zero torque (cvxpy/Clarabel).

    Stated per engine with explicit lever arms (r x d), not with the geometry's maps.
    """
    limits = max_thrust_N(geometry)
    members = [e.index for e in geometry.engines if np.allclose(e.direction, direction)]
    f = cp.Variable(len(members))  # mN: well scaled for the interior-point solver
    lever = np.cross(np.array([geometry.engines[i].position_m for i in members]), direction)
    problem = cp.Problem(
        cp.Maximize(cp.sum(f)), [lever.T @ f == 0, f >= 0, f <= 1e3 * limits[members]]
    )
    problem.solve(solver=cp.CLARABEL)
    return float(problem.value) * 1e-3


def test_burns_are_the_segments_torque_free_and_at_least_the_own_engines_push(paper) -> None:
    """Each burn is a segment's constant mix: no torque, force along its direction only.

    Couples of other faces' engines may help a direction: its thrust is then
    above what its own engines balance among themselves (cvxpy), and the total
    impulse is never below the own-engines schedule's (a feasible point of the LP).
    """
    problem, geometry, segments = paper
    assert len(segments) == 6
    own_impulse = 0.0
    for segment, burn in zip(segments, burn_schedule(segments), strict=True):
        thrust = segment.engine_thrust_N
        assert np.linalg.norm(geometry.torque_map @ thrust) < 1e-12
        np.testing.assert_allclose(
            geometry.force_map @ thrust, burn.force_N * segment.direction_body, atol=1e-12
        )
        assert burn.duration_s == pytest.approx(segment.firing_time_s)
        own = _own_engines_push_N(geometry, segment.direction_body)
        # Four parallel engines: a little under 4 x 0.64 mN when balanced among themselves.
        assert 2.4e-3 < own <= 4 * 0.64e-3 + 1e-9
        own_impulse += own * problem.engines[0].stages * problem.engines[0].stage_life_h * HOUR
    total = sum(s.impulse_Ns for s in segments)
    assert total >= own_impulse * (1 - 1e-7)
    # The paper's y faces: a couple of x engines lets all four y engines fire at full thrust.
    assert segments[0].thrust_N == pytest.approx(4 * 0.64e-3, rel=1e-9)
    assert segments[0].thrust_N > _own_engines_push_N(geometry, segments[0].direction_body)


def test_staged_burns_give_the_budgets_all_faces_dv(paper) -> None:
    """All stages of all directions: within 2 % of the budget's rocket-equation 125 m/s.

    The budget fires every engine at full thrust; balancing the torque throttles
    some engines of each face (about 1 % less thrust).
    """
    problem, geometry, segments = paper
    burns = burn_schedule(segments)
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
    _, _, segments = paper
    burns = burn_schedule(segments, extra=8)
    assert [b.real for b in burns] == [True] * 6 + [False] * 8
    assert [b.group for b in burns[6:]] == [0, 1, 2, 3, 4, 5, 0, 1]


def test_stage_use_and_switches_per_cubesat(paper) -> None:
    problem, geometry, segments = paper
    burns = burn_schedule(segments)
    uses = stage_use(
        problem, geometry, segments, {i: s.firing_time_s for i, s in enumerate(segments)}
    )
    assert [u.cubesat for u in uses] == list(range(1, 25))
    assert all(u.stages == [1, 2, 3] for u in uses)
    # Propellant: each engine's impulse over its exhaust speed, summed independently.
    exhaust = np.array([e.isp_s * problem.constants.standard_gravity_m_s2 for e in problem.engines])
    total = sum(float(np.sum(s.engine_impulse_Ns / exhaust)) for s in segments)
    assert sum(u.propellant_kg for u in uses) == pytest.approx(total, rel=1e-12)
    # An engine at full thrust spends exactly 3 stages; a throttled one less.
    assert max(u.spent_stages for u in uses) == pytest.approx(3.0)
    switches = stage_switch_times_s(problem, geometry, segments, burns)
    assert switches == sorted(switches)
    assert {s[2] for s in switches} == {1, 2, 3}
    assert all(1 <= s[1] <= 24 for s in switches)


def test_a_throttled_stage_lasts_longer(paper) -> None:
    """At half throttle an engine at full thrust spends its first stage after 1000 h, not 500 h."""
    problem, geometry, segments = paper
    burns = burn_schedule(segments)
    end = burns[-1].start_s + burns[-1].duration_s
    half = stage_switch_times_s(
        problem, geometry, segments, burns, (np.array([0.0, end]), np.array([0.5]))
    )
    full = stage_switch_times_s(problem, geometry, segments, burns)
    first_half = min(t for t, _, stage in half if stage == 1)
    first_full = min(t for t, _, stage in full if stage == 1)
    assert first_full == pytest.approx(500 * 3600.0)
    assert first_half == pytest.approx(1000 * 3600.0)
    # Half throttle through a 1500 h burn: one stage and a half, so no third-stage switch.
    assert {stage for _, _, stage in half} == {1}
