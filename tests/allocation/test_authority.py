"""Torque authority polytope, checked against independent linear programs.

References: the geometry's per-axis authority LP
(:func:`casadi_debris.geometry.torque_authority`) and scipy's HiGHS on the
engines themselves: largest alpha with ``alpha tau`` reachable, feasibility
of each vertex, support value of each facet. The LPs are posed in mN and mNm
so that HiGHS' absolute tolerances are small against the numbers.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from casadi_debris.allocation import Allocator, AuthorityPolytope, authority_polytope
from casadi_debris.config import AXIS_NAMES, SIGNED_AXES, Problem
from casadi_debris.errors import AllocationError
from casadi_debris.geometry import Geometry, max_thrust_N, torque_authority
from lp_reference import largest_alpha, net_force, reaches, support

RTOL = 1e-9
N_CUBESATS = 24
MIN_ALIVE = 8
# Far beyond any engine's reach [N m]: the scale of such a demand times its
# size is the authority along it.
BEYOND_REACH_NM = 10.0


# ----------------------------------------------------------------------------- references


def unit_directions(rng: np.random.Generator, count: int) -> np.ndarray:
    directions = rng.normal(size=(count, 3))
    return directions / np.linalg.norm(directions, axis=1, keepdims=True)


def limits_with_failures(geometry: Geometry, failed: set[int] | tuple[int, ...]) -> np.ndarray:
    limits = max_thrust_N(geometry).copy()
    limits[list(failed)] = 0.0
    return limits


def check_polytope(
    polytope: AuthorityPolytope,
    geometry: Geometry,
    limits: np.ndarray,
    free_force: bool,
    directions: np.ndarray,
) -> None:
    """Scale along random directions, vertices and facets, each against its own LP."""
    size_Nm = float(np.abs(polytope.vertices).max())
    assert size_Nm > 0
    # Unit normals, vertices inside every facet.
    np.testing.assert_allclose(np.linalg.norm(polytope.normals, axis=1), 1.0, rtol=1e-12)
    slack = polytope.offsets[None, :] - polytope.vertices @ polytope.normals.T
    assert slack.min() >= -RTOL * size_Nm

    # Along any direction: alpha of a demand far beyond reach = the LP's largest alpha.
    for direction in directions:
        demand = BEYOND_REACH_NM * direction
        reference = largest_alpha(geometry, limits, demand, net_force(free_force), at_most=None)
        found = float(polytope.scale(demand))
        assert abs(found - reference) <= RTOL * max(reference, size_Nm / BEYOND_REACH_NM)
    # Row-wise evaluation gives the same numbers.
    np.testing.assert_allclose(
        polytope.scale(BEYOND_REACH_NM * directions),
        [polytope.scale(BEYOND_REACH_NM * d) for d in directions],
        rtol=1e-14,
    )

    # Every vertex is made by some thrust; every facet touches the reachable set.
    for vertex in polytope.vertices:
        assert reaches(geometry, limits, vertex, net_force(free_force))
    for normal, offset in zip(polytope.normals, polytope.offsets, strict=True):
        value, _ = support(geometry, limits, normal, free_force)
        assert abs(value - offset) <= RTOL * size_Nm
        # A facet, not an edge: its vertices span a plane.
        on_facet = polytope.vertices[np.abs(polytope.vertices @ normal - offset) <= RTOL * size_Nm]
        assert len(on_facet) >= 3
        assert np.linalg.matrix_rank(on_facet[1:] - on_facet[0], tol=RTOL * size_Nm) == 2


# ----------------------------------------------------------------------------- per axis


@pytest.mark.parametrize("failed", [(), (3, 17), (0, 1, 2, 3), (8, 9, 12, 13, 20)])
@pytest.mark.parametrize("free_force", [False, True])
def test_scale_of_a_big_axis_demand_is_the_geometry_torque_authority(
    geometry: Geometry, failed: tuple[int, ...], free_force: bool
) -> None:
    limits = limits_with_failures(geometry, failed)
    available = limits > 0
    expected = torque_authority(geometry, zero_net_force=not free_force, available=available)
    polytope = authority_polytope(
        geometry.torque_map, geometry.force_map, limits, free_force=free_force
    )
    largest = max(expected.values())
    for name in SIGNED_AXES:
        demand = np.zeros(3)
        demand[AXIS_NAMES.index(name[1])] = BEYOND_REACH_NM if name[0] == "+" else -BEYOND_REACH_NM
        found = float(polytope.scale(demand)) * BEYOND_REACH_NM
        assert abs(found - expected[name]) <= RTOL * largest


@pytest.mark.parametrize("failed", [(), (3, 17), (0, 1, 2, 3), (8, 9, 12, 13, 20)])
def test_axis_reach_is_the_linear_programs_authority_per_signed_axis(
    geometry: Geometry, failed: tuple[int, ...]
) -> None:
    limits = limits_with_failures(geometry, failed)
    expected = torque_authority(geometry, zero_net_force=True, available=limits > 0)
    polytope = authority_polytope(geometry.torque_map, geometry.force_map, limits)
    reach = polytope.axis_reach()
    largest = max(expected.values())
    for k, name in enumerate(f"{sign}{axis}" for axis in AXIS_NAMES for sign in "+-"):
        assert abs(reach[k] - expected[name]) <= RTOL * largest, name


def test_allocator_polytope_is_cached_until_the_limits_change(
    problem: Problem, geometry: Geometry
) -> None:
    allocator = Allocator.from_problem(problem, geometry)
    first = allocator.authority_polytope()
    assert allocator.authority_polytope() is first
    assert allocator.authority_polytope(free_force=True) is not first
    allocator.set_failed([5])
    after = allocator.authority_polytope()
    assert after is not first
    expected = torque_authority(geometry, zero_net_force=True, available=allocator.max_thrust_N > 0)
    for name in SIGNED_AXES:
        demand = np.zeros(3)
        demand[AXIS_NAMES.index(name[1])] = BEYOND_REACH_NM if name[0] == "+" else -BEYOND_REACH_NM
        assert float(after.scale(demand)) * BEYOND_REACH_NM == pytest.approx(
            expected[name], rel=RTOL, abs=RTOL * max(expected.values())
        )


def test_scale_is_one_inside_and_for_a_zero_demand(geometry: Geometry) -> None:
    polytope = authority_polytope(geometry.torque_map, geometry.force_map, max_thrust_N(geometry))
    inner = 0.5 * polytope.vertices
    np.testing.assert_array_equal(polytope.scale(inner), 1.0)
    assert float(polytope.scale(np.zeros(3))) == 1.0


# ----------------------------------------------------------------------------- every direction


@pytest.mark.parametrize("free_force", [False, True])
def test_nominal_polytope_matches_linear_programs(geometry: Geometry, free_force: bool) -> None:
    limits = max_thrust_N(geometry)
    polytope = authority_polytope(
        geometry.torque_map, geometry.force_map, limits, free_force=free_force
    )
    rng = np.random.default_rng(20240405)
    check_polytope(polytope, geometry, limits, free_force, unit_directions(rng, 40))


def _is_flat(geometry: Geometry, limits: np.ndarray, free_force: bool) -> bool:
    """Whether the reachable torques lie in a plane (support points of 26 directions, by SVD)."""
    grid = np.array([d for d in itertools.product((-1, 0, 1), repeat=3) if any(d)], dtype=float)
    points = []
    for direction in grid / np.linalg.norm(grid, axis=1, keepdims=True):
        _, thrust = support(geometry, limits, direction, free_force)
        points.append(geometry.torque_map @ thrust)
    points = np.array(points)
    spread = np.linalg.svd(points - points.mean(axis=0), compute_uv=False)
    return bool(spread[-1] <= 1e-9 * max(spread[0], np.finfo(float).tiny))


@settings(
    max_examples=12,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(
    failed=st.sets(st.integers(0, N_CUBESATS - 1), max_size=N_CUBESATS - MIN_ALIVE),
    free_force=st.booleans(),
    seed=st.integers(0, 2**32 - 1),
)
def test_random_failures_match_linear_programs(
    geometry: Geometry, failed: set[int], free_force: bool, seed: int
) -> None:
    limits = limits_with_failures(geometry, failed)
    try:
        polytope = authority_polytope(
            geometry.torque_map, geometry.force_map, limits, free_force=free_force
        )
    except AllocationError:
        # Only a set of torques in a plane may be refused.
        assert _is_flat(geometry, limits, free_force)
        return
    rng = np.random.default_rng(seed)
    check_polytope(polytope, geometry, limits, free_force, unit_directions(rng, 12))


# ----------------------------------------------------------------------------- allocate


@pytest.mark.parametrize("free_force", [False, True])
def test_allocate_saturates_far_beyond_reach_to_the_linear_programs_alpha(
    problem: Problem, geometry: Geometry, free_force: bool
) -> None:
    # Demands up to 1000x the authority: the saturation is still exact.
    allocator = Allocator.from_problem(problem, geometry)
    limits = allocator.max_thrust_N
    rng = np.random.default_rng(20240406)
    for direction in unit_directions(rng, 25):
        for size_Nm in (1e-2, 1e-1, 1.0):
            demand = size_Nm * direction
            result = allocator.allocate(demand, free_force=free_force)
            reference = largest_alpha(geometry, limits, demand, net_force(free_force), at_most=None)
            assert abs(result.scale - reference) <= RTOL * reference
            assert np.all(result.thrust_N >= 0.0) and np.all(result.thrust_N <= limits)


# ----------------------------------------------------------------------------- flat


@pytest.mark.parametrize("free_force", [False, True])
@pytest.mark.parametrize("faces", [("+x", "-x"), ("+y", "-y"), ("+z", "-z")])
def test_engines_on_two_parallel_faces_only_make_a_flat_set_and_are_refused(
    geometry: Geometry, faces: tuple[str, str], free_force: bool
) -> None:
    # Thrust along +-a only: every torque r x f is normal to a.
    alive = np.array([geometry.cubesats[e.cubesat].face in faces for e in geometry.engines])
    limits = np.where(alive, max_thrust_N(geometry), 0.0)
    assert _is_flat(geometry, limits, free_force)
    with pytest.raises(AllocationError, match="flat"):
        authority_polytope(geometry.torque_map, geometry.force_map, limits, free_force=free_force)


# ----------------------------------------------------------------------------- a burn's slice


def test_the_slice_at_a_net_force_holds_exactly_the_torques_reachable_with_it(
    geometry: Geometry,
) -> None:
    """Each vertex is reached with the force delivered (HiGHS, in mN); each facet's
    support value with the force is its offset; at zero force it is the usual polytope."""
    from scipy.optimize import linprog

    g = geometry
    limits = max_thrust_N(g)
    phi = np.array([0.0, -2.3e-3, 0.0])
    polytope = authority_polytope(g.torque_map, g.force_map, limits, force_N=phi)
    bounds = [(0.0, f * 1e3) for f in limits]
    for vertex in polytope.vertices:
        fit = linprog(
            np.zeros(len(limits)),
            A_eq=np.vstack([g.torque_map, g.force_map]),
            b_eq=np.concatenate([vertex, phi]) * 1e3,
            bounds=bounds,
            method="highs",
        )
        assert fit.status == 0
    for normal, offset in zip(polytope.normals, polytope.offsets, strict=True):
        best = linprog(
            -(normal @ g.torque_map),
            A_eq=g.force_map,
            b_eq=phi * 1e3,
            bounds=bounds,
            method="highs",
        )
        assert -best.fun * 1e-3 == pytest.approx(offset, rel=1e-7, abs=1e-12)
    zero = authority_polytope(g.torque_map, g.force_map, limits, force_N=np.zeros(3))
    usual = authority_polytope(g.torque_map, g.force_map, limits)
    assert np.allclose(zero.axis_reach(), usual.axis_reach(), rtol=1e-12)
    # Delivering the force leaves less torque.
    assert np.all(polytope.axis_reach() <= usual.axis_reach() * (1 + 1e-12))
    with pytest.raises(AllocationError):
        authority_polytope(g.torque_map, g.force_map, limits, free_force=True, force_N=phi)


def test_a_flat_polytope_names_the_axes_without_torque() -> None:
    torque_map = np.array([[1.0, -1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, -1.0]])
    with pytest.raises(AllocationError, match=r"cannot torque about \+y, -y at zero net force"):
        authority_polytope(torque_map, np.zeros((3, 4)), np.ones(4), free_force=True)
