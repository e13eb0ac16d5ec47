"""Failure sets and the authority they leave, against itertools, math.comb and independent LPs."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from casadi_debris.config import SIGNED_AXES, load_problem, signed_axis_vector
from casadi_debris.geometry import Authority, build_geometry, max_thrust_N
from casadi_debris.studies.failures import (
    authority_ratio,
    authority_without,
    axis_ratios,
    failure_sets,
    set_authority,
    weakest_axis,
)
from lp_reference import ZERO_FORCE, largest_alpha


@pytest.mark.parametrize(("n", "size"), [(5, 0), (5, 1), (6, 2), (7, 3), (4, 4)])
def test_every_set_once_increasing_in_lexicographic_order(n, size):
    members = [3 * i + 1 for i in reversed(range(n))]
    sets = failure_sets(members, size)
    assert len(sets) == len(set(sets)) == math.comb(n, size)
    assert all(list(s) == sorted(s) and set(s) <= set(members) for s in sets)
    assert sets == sorted(sets)


def test_ratio_is_inf_without_disturbance_and_matches_division_otherwise():
    authority = np.array([[1.0, 2.0, 3.0, 4.0, 0.0, 6.0], [0.5, 0.5, 0.5, 0.5, 0.5, 0.5]])
    disturbance = np.array([0.5, 0.0, 2.0])
    ratio = authority_ratio(authority, disturbance)
    np.testing.assert_array_equal(ratio[:, 2:4], np.inf)
    np.testing.assert_allclose(ratio[0, [0, 1, 4, 5]], [2.0, 4.0, 0.0, 3.0])
    named = axis_ratios(Authority(authority[0], zero_net_force=True), disturbance)
    assert list(named) == list(SIGNED_AXES)
    assert named == dict(zip(SIGNED_AXES, ratio[0].tolist(), strict=True))


def _independent_Nm(geometry, failed) -> np.ndarray:
    """Per signed axis, the largest multiple of 1 mN m the engines left reach, by the
    tests' own LP."""
    limits = np.where(np.isin(geometry.engine_cubesat, failed), 0.0, max_thrust_N(geometry))
    return np.array(
        [
            1e-3
            * largest_alpha(
                geometry, limits, 1e-3 * signed_axis_vector(n), ZERO_FORCE, at_most=None
            )
            for n in SIGNED_AXES
        ]
    )


def test_authority_without_failed_cubesats_is_an_independent_lp():
    geometry = build_geometry(load_problem("two_per_face"))
    for failed in [(), (0,), (3, 7), (0, 1, 2, 3, 4, 5)]:
        np.testing.assert_allclose(
            authority_without(geometry, failed).torque_Nm,
            _independent_Nm(geometry, failed),
            rtol=1e-7,
            atol=1e-12,
        )


def test_worst_per_axis_and_weakest_ratio_against_brute_force():
    geometry = build_geometry(load_problem("two_per_face"))
    disturbance = np.array([0.7e-3, 0.7e-3, 0.7e-3])
    found = set_authority(
        range(len(geometry.cubesats)), 2, lambda s: authority_without(geometry, s)
    )
    every = {
        s: authority_without(geometry, s).torque_Nm
        for s in itertools.combinations(range(len(geometry.cubesats)), 2)
    }
    assert found.sets == tuple(every)
    least, where = found.worst_per_axis()
    for axis in range(len(SIGNED_AXES)):
        lowest = min(v[axis] for v in every.values())
        # Symmetric sets tie to round-off: the first of them is reported.
        first = next(s for s, v in every.items() if v[axis] <= lowest + 1e-9 * abs(lowest))
        assert least[axis] == lowest and where[axis] == first
    weakest = found.weakest_ratio(disturbance)
    np.testing.assert_array_equal(
        weakest, [min(v / np.repeat(disturbance, 2)) for v in every.values()]
    )


def test_weakest_axis_is_the_least_ratio_then_the_least_authority():
    authority = Authority(np.array([3.0, 2.0, 5.0, 1.0, 4.0, 6.0]), zero_net_force=True)
    assert weakest_axis(axis_ratios(authority, np.array([1.0, 1.0, 1.0])), authority) == "-y"
    # Without disturbance every ratio is inf: the least authority decides.
    assert weakest_axis(axis_ratios(authority, np.zeros(3)), authority) == "-y"
    assert weakest_axis(axis_ratios(authority, np.array([4.0, 0.0, 1.0])), authority) == "-x"
