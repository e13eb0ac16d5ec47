"""Random swarms: any CubeSats on any faces with 1 to 4 engines each, checked against LPs.

For each drawn swarm and torque direction d, the largest reachable multiple
alpha* of d (zero net force, every engine within its limit) comes from an
independent LP. The allocator must meet 0.5 alpha* d exactly and, asked for
2 alpha* d, keep the direction at the scale alpha* / 2, never exceeding a limit.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scipy.optimize import linprog

from casadi_debris.allocation import Allocator
from casadi_debris.config import SIGNED_AXES, problem_from_dict, signed_axis_vector
from casadi_debris.errors import AllocationError
from casadi_debris.geometry import build_geometry

HUB_SIZE_M = np.array([0.75, 3.0, 1.0])


def _position_on_face(face: str, u: float, v: float) -> list[float]:
    axis = "xyz".index(face[1])
    point = np.empty(3)
    others = [a for a in range(3) if a != axis]
    point[axis] = HUB_SIZE_M[axis] if face[0] == "+" else 0.0
    point[others[0]], point[others[1]] = u * HUB_SIZE_M[others[0]], v * HUB_SIZE_M[others[1]]
    return point.tolist()


unit = st.floats(0.0, 1.0)
engine = st.fixed_dictionaries(
    {
        "direction": st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3).filter(
            lambda d: float(np.linalg.norm(d)) > 0.1
        ),
        "offset_m": st.lists(st.floats(-0.05, 0.05), min_size=3, max_size=3),
    }
)
cubesat = st.builds(
    lambda face, u, v, engines: {
        "position_corner_m": _position_on_face(face, u, v),
        "mass_kg": 3.0,
        "inertia_kgm2": [0.05, 0.05, 0.01],
        "face": face,
        "engines": engines,
    },
    st.sampled_from(SIGNED_AXES),
    unit,
    unit,
    st.lists(engine, min_size=1, max_size=4),
)


def _problem(paper_data: dict, cubesats: list[dict]) -> object:
    data = {key: value for key, value in paper_data.items() if key != "cubesat_layout"}
    data["cubesats"] = cubesats
    return problem_from_dict(data)


def _largest_multiple(geometry, limits: np.ndarray, direction: np.ndarray) -> float:
    """max alpha: B f = alpha d, F f = 0, 0 <= f <= limits (an LP in [f, alpha])."""
    n = len(limits)
    a_eq = np.zeros((6, n + 1))
    a_eq[:3, :n], a_eq[:3, n] = geometry.torque_map, -direction
    a_eq[3:, :n] = geometry.force_map
    bounds = [(0.0, float(f)) for f in limits] + [(0.0, None)]
    cost = np.zeros(n + 1)
    cost[n] = -1.0
    result = linprog(cost, A_eq=a_eq, b_eq=np.zeros(6), bounds=bounds, method="highs")
    assert result.status == 0
    return float(result.x[n])


@pytest.mark.filterwarnings("ignore")
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    cubesats=st.lists(cubesat, min_size=1, max_size=40),
    axis=st.sampled_from(SIGNED_AXES),
    tilt=st.lists(st.floats(-0.5, 0.5), min_size=3, max_size=3),
)
def test_random_swarms_meet_reachable_torque_and_keep_direction(
    paper_data: dict, cubesats: list[dict], axis: str, tilt: list[float]
) -> None:
    problem = _problem(paper_data, cubesats)
    geometry = build_geometry(problem)
    direction = signed_axis_vector(axis) + np.array(tilt)
    direction /= np.linalg.norm(direction)
    limits = np.array([e.max_thrust_N for e in geometry.engines])
    alpha = _largest_multiple(geometry, limits, direction)
    assume(alpha > 1e-9)
    try:
        allocator = Allocator.from_problem(problem, geometry)
        reachable = allocator.allocate(0.5 * alpha * direction)
        beyond = allocator.allocate(2.0 * alpha * direction)
    except AllocationError as error:  # a flat torque set (fewer than 3 dimensions)
        assert "flat" in str(error)
        assume(False)
        return
    scale = np.abs(geometry.torque_map).sum() * limits.max()
    for result in (reachable, beyond):
        assert np.all(result.thrust_N >= 0.0)
        assert np.all(result.thrust_N <= limits * (1 + 1e-9))
        np.testing.assert_allclose(result.force_N, 0.0, atol=1e-9 * scale)
    assert reachable.feasible
    np.testing.assert_allclose(reachable.torque_Nm, 0.5 * alpha * direction, atol=1e-9 * scale)
    assert not beyond.feasible
    assert beyond.scale == pytest.approx(0.5, rel=1e-6)
    np.testing.assert_allclose(beyond.torque_Nm, alpha * direction, atol=1e-8 * scale)
