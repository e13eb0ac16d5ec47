"""``open_loop_rigid`` against an independent rigid-body integration.

Reference: Euler's equations ``J w_dot = tau - w x (J w)`` and the kinematics
``q_dot = 1/2 q (x) [0, w]`` (scalar first) written here in numpy and
integrated by scipy's DOP853 at tight tolerances, restarted at every knot.
The inertia is summed here from the problem's parts by the parallel-axis
theorem (hub, CubeSats at the face corners, arrays at theta_SA = 0), not
taken from the geometry module.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from casadi_debris.config import AXIS_NAMES, SIGNED_AXES, Problem
from casadi_debris.dynamics import build_model
from casadi_debris.simulation import SimulationError, open_loop_rigid

# DOP853 at rtol 1e-12 against CVODES at reltol 1e-12: both far below this.
TRAJECTORY_TOL = 1e-8
KNOTS_S = np.array([0.0, 30.0, 75.0, 140.0, 200.0])
TORQUE_NM = np.array(
    [
        [0.10, -0.05, 0.08],
        [-0.15, 0.12, 0.00],
        [0.00, 0.00, -0.20],
        [0.05, 0.05, 0.05],
        [-0.08, 0.03, 0.10],
    ]
)
DURATION_S = 260.0


def parallel_axis(mass_kg: float, offset_m: np.ndarray) -> np.ndarray:
    return mass_kg * (offset_m @ offset_m * np.eye(3) - np.outer(offset_m, offset_m))


def independent_inertia(problem: Problem) -> np.ndarray:
    """Full rigid inertia about the combined CoG, summed part by part (theta_SA = 0)."""
    hub, sats, arrays = problem.hub, problem.cubesat_layout, problem.arrays
    assert sats is not None and sats.kind == "face_corners"
    # The array inertia below is written for theta_SA = 0.
    assert all(array.angle_deg == 0.0 for array in arrays)
    centre = hub.size_m / 2.0
    parts = [(hub.mass_kg, hub.cog_corner_m, hub.inertia_kgm2)]
    for face in SIGNED_AXES:
        axis = AXIS_NAMES.index(face[1])
        sign = 1.0 if face[0] == "+" else -1.0
        u, w = (a for a in range(3) if a != axis)
        # CubeSat axes: x (thrust) along the face normal, long axis z next, y after.
        own = np.zeros((3, 3))
        own[axis, axis] = sats.inertia_kgm2[0]
        own[(axis + 1) % 3, (axis + 1) % 3] = sats.inertia_kgm2[2]
        own[(axis + 2) % 3, (axis + 2) % 3] = sats.inertia_kgm2[1]
        for s1 in (1.0, -1.0):
            for s2 in (1.0, -1.0):
                position = centre.copy()
                position[axis] += sign * (centre[axis] + sats.standoff_m)
                position[u] += s1 * (1 - sats.edge_margin_fraction) * centre[u]
                position[w] += s2 * (1 - sats.edge_margin_fraction) * centre[w]
                parts.append((sats.mass_kg, position, own))
    for array in arrays:
        # theta_SA = 0: normal along x, length along the hinge axis (z), width along y.
        assert abs(array.direction[2]) == 1.0
        moments = array.inertia_kgm2
        own = np.diag([moments[2], moments[1], moments[0]])
        cog = array.hinge_corner_m + 0.5 * array.length_m * array.direction
        parts.append((array.mass_kg, cog, own))
    mass = sum(m for m, _, _ in parts)
    cog = sum(m * r for m, r, _ in parts) / mass
    return sum(own + parallel_axis(m, r - cog) for m, r, own in parts)


def quaternion_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.concatenate(
        [[a[0] * b[0] - a[1:] @ b[1:]], a[0] * b[1:] + b[0] * a[1:] + np.cross(a[1:], b[1:])]
    )


def reference_trajectory(
    inertia: np.ndarray, knots: np.ndarray, torque: np.ndarray, grid: np.ndarray
) -> np.ndarray:
    """[q (4), w (3)] at ``grid`` by DOP853, restarted at every grid point."""
    inverse = np.linalg.inv(inertia)

    def rate(_t: float, y: np.ndarray, tau: np.ndarray) -> np.ndarray:
        q, w = y[:4], y[4:]
        q_dot = 0.5 * quaternion_product(q, np.concatenate([[0.0], w]))
        w_dot = inverse @ (tau - np.cross(w, inertia @ w))
        return np.concatenate([q_dot, w_dot])

    states = np.zeros((len(grid), 7))
    states[0, 0] = 1.0
    for i in range(len(grid) - 1):
        held = torque[np.searchsorted(knots, grid[i], side="right") - 1]
        solution = solve_ivp(
            rate,
            (grid[i], grid[i + 1]),
            states[i],
            method="DOP853",
            rtol=1e-12,
            atol=1e-14,
            args=(held,),
        )
        assert solution.success
        states[i + 1] = solution.y[:, -1]
    return states


@pytest.fixture(scope="module")
def table_run(problem: Problem):
    return open_loop_rigid(problem, KNOTS_S, TORQUE_NM, DURATION_S)


def test_inertia_is_the_full_rigid_inertia(problem: Problem, table_run) -> None:
    expected = independent_inertia(problem)
    np.testing.assert_allclose(table_run.inertia_kgm2, expected, rtol=1e-12, atol=1e-12)
    model = build_model(problem)
    np.testing.assert_allclose(
        table_run.inertia_kgm2, np.asarray(model.rigid_inertia(model.nominal_parameters))
    )


def test_grid_and_held_torque(table_run) -> None:
    grid = table_run.time_s
    assert grid[0] == 0.0 and grid[-1] == DURATION_S
    assert set(KNOTS_S) <= set(grid)
    assert np.all(np.diff(grid) > 0) and np.diff(grid).max() <= 1.0 + 1e-12
    for t, tau in zip(grid, table_run.torque_Nm, strict=True):
        row = max(i for i, k in enumerate(KNOTS_S) if k <= t)
        np.testing.assert_array_equal(tau, TORQUE_NM[row])


def test_matches_independent_integration(problem: Problem, table_run) -> None:
    inertia = independent_inertia(problem)
    expected = reference_trajectory(inertia, KNOTS_S, TORQUE_NM, table_run.time_s)
    # Large enough that the gyroscopic coupling and the kinematics are not small.
    assert np.abs(table_run.rate_rad_s).max() > 0.01
    assert abs(table_run.quaternion_BN[-1, 0]) < 0.9
    np.testing.assert_allclose(
        table_run.quaternion_BN, expected[:, :4], rtol=0, atol=TRAJECTORY_TOL
    )
    np.testing.assert_allclose(table_run.rate_rad_s, expected[:, 4:], rtol=0, atol=TRAJECTORY_TOL)
    np.testing.assert_allclose(np.linalg.norm(table_run.quaternion_BN, axis=1), 1.0, atol=1e-10)


def test_last_row_unused_without_duration(problem: Problem) -> None:
    first = open_loop_rigid(problem, KNOTS_S, TORQUE_NM)
    changed = TORQUE_NM.copy()
    changed[-1] = [1.0, -1.0, 1.0]
    second = open_loop_rigid(problem, KNOTS_S, changed)
    assert first.time_s[-1] == KNOTS_S[-1]
    np.testing.assert_array_equal(first.quaternion_BN, second.quaternion_BN)
    np.testing.assert_array_equal(first.rate_rad_s, second.rate_rad_s)


def test_zero_torque_stays_at_rest(problem: Problem) -> None:
    result = open_loop_rigid(problem, [0.0, 5.0], np.zeros((2, 3)), 12.0)
    np.testing.assert_array_equal(
        result.quaternion_BN, np.tile([1.0, 0, 0, 0], (len(result.time_s), 1))
    )
    np.testing.assert_array_equal(result.rate_rad_s, 0.0)


def test_small_angle_constant_torque(problem: Problem) -> None:
    # From rest under a constant torque: w = J^-1 tau t and theta = 1/2 J^-1 tau t^2
    # to first order. The gyroscopic term w x Jw and the kinematic nonlinearity
    # are of relative order kappa(J) * |theta| (kappa: condition number of J).
    tau = np.array([1.0e-3, -2.0e-3, 1.5e-3])
    t = 1.0
    result = open_loop_rigid(problem, [0.0], tau[None, :], t)
    inertia = independent_inertia(problem)
    rate = np.linalg.solve(inertia, tau) * t
    angle = 0.5 * rate * t
    bound = np.linalg.cond(inertia) * np.linalg.norm(angle)
    assert bound < 1e-3
    measured_angle = 2.0 * result.quaternion_BN[-1, 1:]
    assert np.linalg.norm(measured_angle - angle) <= bound * np.linalg.norm(angle)
    assert np.linalg.norm(result.rate_rad_s[-1] - rate) <= bound * np.linalg.norm(rate)


@pytest.mark.parametrize(
    ("knots", "torque", "duration", "match"),
    [
        ([0.0, 10.0, 10.0], np.zeros((3, 3)), None, "increase"),
        ([0.0, 20.0, 10.0], np.zeros((3, 3)), None, "increase"),
        ([1.0, 10.0], np.zeros((2, 3)), None, "start at 0"),
        ([0.0, np.nan], np.zeros((2, 3)), None, "finite"),
        ([0.0, 10.0], np.array([[0.0, np.nan, 0.0], [0.0, 0.0, 0.0]]), None, "finite"),
        ([0.0, 10.0], np.array([[0.0, np.inf, 0.0], [0.0, 0.0, 0.0]]), None, "finite"),
        ([0.0, 10.0], np.zeros((2, 2)), None, "shape|\\(k, 3\\)"),
        ([0.0, 10.0], np.zeros((3, 3)), None, "\\(k, 3\\)"),
        ([[0.0, 10.0]], np.zeros((2, 3)), None, "\\(k, 3\\)"),
        ([], np.zeros((0, 3)), None, "\\(k, 3\\)"),
        ([0.0], np.zeros((1, 3)), None, "duration"),
        ([0.0, 10.0], np.zeros((2, 3)), -5.0, "duration"),
    ],
)
def test_bad_input(problem: Problem, knots, torque, duration, match) -> None:
    with pytest.raises(SimulationError, match=match):
        open_loop_rigid(problem, knots, torque, duration)
