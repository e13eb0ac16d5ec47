"""Placement, mass properties and torque authority against the paper and independent checks."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from casadi_debris.config import AXIS_NAMES, SIGNED_AXES, signed_axis_vector
from casadi_debris.geometry import max_thrust_N, torque_authority
from casadi_debris.report import paper_figure

# The paper's figures and accepted tolerances (casadi_debris/data/paper_reference.toml).
PAPER_MASS = paper_figure("mass_kg")
PAPER_INERTIA_DIAG = paper_figure("inertia_hub_cubesats_diag_kgm2")
PAPER_TORQUE = paper_figure("torque_max_mNm")


def test_total_mass(geometry):
    assert PAPER_MASS.accepts(geometry.mass_kg), geometry.mass_kg


def test_hub_cubesats_inertia_against_paper(geometry):
    diag = np.diag(geometry.inertia_hub_cubesats_kgm2)
    assert PAPER_INERTIA_DIAG.accepts(diag), diag
    # The CubeSats sit symmetrically about the hub centre: off-diagonals stay the hub's,
    # but for the small parallel-axis term of the combined-CoG shift.
    np.testing.assert_allclose(
        geometry.inertia_hub_cubesats_kgm2[[0, 0, 1], [1, 2, 2]], [1.0, 2.0, -1.0], atol=0.05
    )


def test_torque_authority_against_paper(geometry):
    authority = torque_authority(geometry)
    for sign in "+-":
        torque_mNm = [authority[sign + axis] * 1e3 for axis in AXIS_NAMES]
        assert PAPER_TORQUE.accepts(torque_mNm), (sign, torque_mNm)


def test_cog_by_hand(problem, geometry):
    # Hub and CubeSats centred on the hub centre; arrays' CoGs at (0.4, 1.4) and
    # symmetric in z: only 84 kg of arrays pull the CoG off the hub centre.
    arrays_kg = sum(array.mass_kg for array in problem.arrays)
    expected = np.array(
        [0.375 + arrays_kg * (0.4 - 0.375) / 668.0, 1.5 + arrays_kg * (1.4 - 1.5) / 668.0, 0.5]
    )
    np.testing.assert_allclose(geometry.cog_corner_m, expected, atol=1e-12)


def test_cubesats_on_faces_thrusting_inward(problem, geometry):
    size = problem.hub.size_m
    assert len(geometry.cubesats) == 24
    for face in SIGNED_AXES:
        mounts = [m for m in geometry.cubesats if m.face == face]
        assert len(mounts) == 4
        normal = signed_axis_vector(face)
        axis = AXIS_NAMES.index(face[1])
        for mount in mounts:
            corner = mount.position_m + geometry.cog_corner_m
            assert corner[axis] == pytest.approx(size[axis] if face[0] == "+" else 0.0)
            (engine,) = (geometry.engines[i] for i in mount.engines)
            np.testing.assert_array_equal(engine.direction, -normal)
            np.testing.assert_array_equal(engine.position_m, mount.position_m)
            others = [a for a in range(3) if a != axis]
            # 10 % of the half edge in from the edges
            inset = np.minimum(corner[others], size[others] - corner[others])
            np.testing.assert_allclose(inset, 0.1 * size[others] / 2)


def test_torque_map_is_lever_cross_force(geometry):
    for i, engine in enumerate(geometry.engines):
        np.testing.assert_allclose(
            geometry.torque_map[:, i], np.cross(engine.position_m, engine.direction)
        )
        np.testing.assert_array_equal(geometry.force_map[:, i], engine.direction)


def _dual_authority(torque_map, force_map, limits, axis, sign, zero_force):
    """Authority by the dual LP: min u^T s, s >= c - A^T y, s >= 0 (strong duality)."""
    from scipy.optimize import linprog

    others = [a for a in range(3) if a != axis]
    a_eq = torque_map[others]
    if zero_force:
        a_eq = np.vstack([a_eq, force_map])
    c = sign * torque_map[axis]
    n, m = len(limits), len(a_eq)
    # variables [s (n), y (m)]; constraint -s - A^T y <= -c
    result = linprog(
        np.concatenate([limits, np.zeros(m)]),
        A_ub=np.hstack([-np.eye(n), -a_eq.T]),
        b_ub=-c,
        bounds=[(0, None)] * n + [(None, None)] * m,
        method="highs",
    )
    return result.fun


@pytest.mark.parametrize("zero_force", [False, True])
def test_lp_authority_equals_dual_lp(geometry, zero_force):
    authority = torque_authority(geometry, zero_net_force=zero_force)
    limits = max_thrust_N(geometry)
    for name in SIGNED_AXES:
        dual = _dual_authority(
            geometry.torque_map,
            geometry.force_map,
            limits,
            AXIS_NAMES.index(name[1]),
            1.0 if name[0] == "+" else -1.0,
            zero_force,
        )
        assert authority[name] == pytest.approx(dual, rel=1e-9)


def _vertex_enumeration(torque_map, limits, axis, sign):
    """Max pure torque by enumerating every vertex of {0 <= f <= u, A f = 0}."""
    others = [a for a in range(3) if a != axis]
    a_eq = torque_map[others]
    n = len(limits)
    best = 0.0
    # A vertex has at most rank(A) = 2 entries strictly inside their bounds.
    for free in itertools.chain(
        [()], itertools.combinations(range(n), 1), itertools.combinations(range(n), 2)
    ):
        fixed = [i for i in range(n) if i not in free]
        for pattern in itertools.product((0.0, 1.0), repeat=len(fixed)):
            f = np.zeros(n)
            f[fixed] = np.array(pattern) * limits[fixed]
            if free:
                residual = -a_eq[:, fixed] @ f[fixed]
                solution, *_ = np.linalg.lstsq(a_eq[:, list(free)], residual, rcond=None)
                f[list(free)] = solution
            if np.any(f < -1e-12) or np.any(f > limits + 1e-12):
                continue
            if np.linalg.norm(a_eq @ f) > 1e-12:
                continue
            best = max(best, sign * float(torque_map[axis] @ f))
    return best


def test_lp_authority_equals_vertex_enumeration_with_failures(geometry):
    # Ten working engines keep the enumeration small (2^10 patterns x 56 free sets).
    rng = np.random.default_rng(7)
    available = np.zeros(24, dtype=bool)
    available[rng.choice(24, size=10, replace=False)] = True
    authority = torque_authority(geometry, available=available)
    limits = max_thrust_N(geometry)[available]
    for name in SIGNED_AXES:
        brute = _vertex_enumeration(
            geometry.torque_map[:, available],
            limits,
            AXIS_NAMES.index(name[1]),
            1.0 if name[0] == "+" else -1.0,
        )
        assert authority[name] == pytest.approx(brute, rel=1e-9, abs=1e-15)


def test_zero_net_force_never_raises_authority(geometry):
    free = torque_authority(geometry)
    balanced = torque_authority(geometry, zero_net_force=True)
    for name in SIGNED_AXES:
        assert balanced[name] <= free[name] + 1e-15


def test_the_authority_reads_by_signed_axis_and_by_named_arrays(geometry):
    """One type for the authority: its mapping, its arrays and its mN m edge agree with
    each other and with the six values of the LP, in ``SIGNED_AXES`` order."""
    from casadi_debris.errors import CasadiDebrisError
    from casadi_debris.geometry import Authority

    authority = torque_authority(geometry, zero_net_force=True)
    assert isinstance(authority, Authority) and authority.zero_net_force
    assert list(authority) == list(SIGNED_AXES)
    values = [authority[name] for name in SIGNED_AXES]
    assert np.array_equal(authority.torque_Nm, values)
    for i, axis in enumerate(AXIS_NAMES):
        assert authority.positive_Nm[i] == authority[f"+{axis}"]
        assert authority.negative_Nm[i] == authority[f"-{axis}"]
        assert authority.weakest_Nm[i] == min(authority[f"+{axis}"], authority[f"-{axis}"])
    assert authority.to_mNm() == {
        name: value * 1e3 for name, value in zip(SIGNED_AXES, values, strict=True)
    }
    # Equal to a mapping of the same figures (the dicts it replaces), frozen.
    assert authority == dict(zip(SIGNED_AXES, values, strict=True))
    assert authority != dict(zip(SIGNED_AXES, [*values[:-1], values[-1] + 1.0], strict=True))
    with pytest.raises(ValueError, match="read-only"):
        authority.torque_Nm[0] = 0.0
    with pytest.raises(CasadiDebrisError, match="six signed axes"):
        Authority(np.ones(3), zero_net_force=False)


def test_full_rigid_inertia_adds_arrays(problem, geometry):
    # Each array: principal inertia rotated into B plus the parallel-axis term of its CoG.
    assert np.all(np.linalg.eigvalsh(geometry.inertia_arrays_kgm2) > 0)
    np.testing.assert_allclose(
        geometry.inertia_total_kgm2,
        geometry.inertia_hub_cubesats_kgm2 + geometry.inertia_arrays_kgm2,
    )
    # About z (the hinge axis) each array adds its length-axis inertia plus m d^2 for its
    # CoG's distance d from the combined CoG in the x-y plane.
    dx, dy = 0.4 - geometry.cog_corner_m[0], 1.4 - geometry.cog_corner_m[1]
    expected = 2 * (17.0 + problem.arrays[0].mass_kg * (dx**2 + dy**2))
    assert geometry.inertia_arrays_kgm2[2, 2] == pytest.approx(expected, rel=1e-12)
