"""Closed-loop runs (``simulate``) checked against independent computations.

References used here, none of them the simulation's own code:

- attitude errors recomputed in numpy from the logged quaternions;
- torque and force maps built here from the CubeSat corner layout and the
  combined CoG (parallel sums of the problem's masses);
- the reachable torques by scipy's HiGHS linear programs (largest multiple
  of a torque the engines make at zero net force), posed in mN and mNm;
- propellant and firing time as sums of the logged thrust, and stage
  depletion times from the cumulative mass flow;
- CVODES (the simulation's alternative integrator) for the fixed-step RK4.

Runs are shared per module. The paper's figures and their tolerances (slew
max error, slew fuel, pointing error over one orbit) are those of
casadi_debris/data/paper_reference.toml.
"""

from __future__ import annotations

import copy
import json
import math
import tomllib
from typing import Any

import control
import numpy as np
import pytest
from scipy.optimize import linprog

from casadi_debris.allocation import PropulsionState
from casadi_debris.config import (
    AXIS_NAMES,
    SIGNED_AXES,
    Problem,
    default_controller_path,
    default_problem_path,
    load_problem,
    problem_from_dict,
)
from casadi_debris.dynamics import Model, build_model
from casadi_debris.geometry import torque_authority
from casadi_debris.guidance import Reference, sample_reference, scenario_reference
from casadi_debris.report import paper_figure
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import (
    ClosedLoopResult,
    LoopSettings,
    SimulationError,
    simulate_closed_loop,
)
from casadi_debris.simulation import _closed_loop as closed_loop_module

PROBLEMS = default_problem_path().parent
ARCSEC_PER_RAD = 180.0 / math.pi * 3600.0
# The paper's figures (Sections IV.A and IV.B) with their accepted tolerances.
PAPER_SLEW_MAX_ERROR = paper_figure("slew_max_error_deg")
PAPER_SLEW_FUEL = paper_figure("slew_fuel_kg")
PAPER_POINTING_ERROR = paper_figure("pointing").component("nominal_error_arcsec")
# The allocator's promise: its torque equals alpha * demand to 1e-9 (relative).
ALLOCATION_RTOL = 1e-9
# HiGHS feasibility tolerances set in the LPs below (on mN / mNm scaled rows).
LP_TOLERANCE = 1e-10
# alpha from the LP against the simulation's facet formula: both exact up to
# the LP tolerance and the polytope's SUPPORT_RTOL (1e-9).
ALPHA_TOL = 1e-8
FAILURE_TIME_S = 300.0
# Shortened failure run: the failure at 300 s plus 100 s of flying without
# the engines (the full slew is in the slow test). See
# test_failed_engines_keep_the_allocator_fast for why not longer.
FAILURE_RUN_S = 400.0


# --------------------------------------------------------------------------- helpers


def quaternion_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product of scalar-first quaternions, row-wise, shape (n, 4)."""
    a0, av = a[:, :1], a[:, 1:]
    b0, bv = b[:, :1], b[:, 1:]
    return np.hstack(
        [
            a0 * b0 - np.sum(av * bv, axis=1, keepdims=True),
            a0 * bv + b0 * av + np.cross(av, bv),
        ]
    )


def error_vector(q_reference: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Doubled vector part of q_ref^-1 (x) q, short way round, shape (n, 3)."""
    conjugate = q_reference * np.array([1.0, -1.0, -1.0, -1.0])
    error = quaternion_product(conjugate, q)
    return 2.0 * np.where(error[:, :1] >= 0, 1.0, -1.0) * error[:, 1:]


def error_angle_rad(q_reference: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Rotation angle between reference and attitude, shape (n,)."""
    cosine = np.abs(np.sum(q_reference * q, axis=1)) / (
        np.linalg.norm(q_reference, axis=1) * np.linalg.norm(q, axis=1)
    )
    return 2.0 * np.arccos(np.clip(cosine, -1.0, 1.0))


def engine_maps(problem: Problem) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions about the combined CoG, torque map B and force map F, built here.

    CubeSats at the four corners of every face (inset by the edge margin),
    faces in the order +x, -x, +y, -y, +z, -z, thrusting along the inward normal.
    """
    hub, sats, arrays = problem.hub, problem.cubesat_layout, problem.arrays
    assert sats is not None and sats.kind == "face_corners"
    centre = hub.size_m / 2.0
    positions, directions = [], []
    for face in SIGNED_AXES:
        axis = AXIS_NAMES.index(face[1])
        sign = 1.0 if face[0] == "+" else -1.0
        u, w = (a for a in range(3) if a != axis)
        for s1 in (1.0, -1.0):
            for s2 in (1.0, -1.0):
                position = centre.copy()
                position[axis] += sign * (centre[axis] + sats.standoff_m)
                position[u] += s1 * (1 - sats.edge_margin_fraction) * centre[u]
                position[w] += s2 * (1 - sats.edge_margin_fraction) * centre[w]
                positions.append(position)
                direction = np.zeros(3)
                direction[axis] = -sign
                directions.append(direction)
    masses = [hub.mass_kg] + [sats.mass_kg] * len(positions)
    points = [hub.cog_corner_m, *positions]
    for array in arrays:
        masses.append(array.mass_kg)
        points.append(array.hinge_corner_m + 0.5 * array.length_m * array.direction)
    cog = sum(m * p for m, p in zip(masses, points, strict=True)) / sum(masses)
    r = np.array(positions) - cog
    force = np.array(directions).T
    return r, np.cross(r, force.T).T, force


def largest_multiple(
    torque_Nm: np.ndarray, torque_map: np.ndarray, force_map: np.ndarray, limits_N: np.ndarray
) -> float:
    """Largest alpha (capped at 2) with alpha * torque made at zero net force, by LP.

    Unknowns x = f / f_max in [0, 1] and alpha; rows in mNm and mN.
    """
    n = len(limits_N)
    scaled_torque = torque_map * limits_N * 1e3
    scaled_force = force_map * limits_N * 1e3
    a_eq = np.vstack(
        [
            np.hstack([scaled_torque, -1e3 * torque_Nm[:, None]]),
            np.hstack([scaled_force, np.zeros((3, 1))]),
        ]
    )
    result = linprog(
        np.append(np.zeros(n), -1.0),
        A_eq=a_eq,
        b_eq=np.zeros(6),
        bounds=[(0.0, 1.0)] * n + [(0.0, 2.0)],
        method="highs",
        options={
            "primal_feasibility_tolerance": LP_TOLERANCE,
            "dual_feasibility_tolerance": LP_TOLERANCE,
        },
    )
    assert result.status == 0, result.message
    return float(result.x[-1])


def truncated(reference: Reference, end_s: float) -> Reference:
    keep = reference.time_s <= end_s + 1e-9
    return Reference(
        reference.time_s[keep], reference.quaternion_BN[keep], reference.slew, reference.start_s
    )


def fuel_from_thrust(result: ClosedLoopResult, problem: Problem) -> np.ndarray:
    """Propellant per CubeSat: sum of thrust * dt / (Isp g0), shape (n_cubesats,)."""
    exhaust = problem.engine.isp_s * problem.constants.standard_gravity_m_s2
    return result.thrust_N.sum(axis=0) * result.control_period_s / exhaust


def propellant_atol(result: ClosedLoopResult) -> float:
    """Round-off of propellant kept as (full stage - burns): one spacing of the
    stage load per subtraction, at most one per 100-step stretch or event."""
    capacity = float(result.propulsion.stage_capacity_kg.max())
    return np.spacing(capacity) * (len(result.thrust_N) / 100 + len(result.events) + 10)


def stage_limit_N(problem: Problem) -> float:
    return problem.engine.thrust_per_stage_mN * 1e-3


def crossing_time_s(thrust_N: np.ndarray, dt_s: float, exhaust: float, mass_kg: float) -> float:
    """When the cumulative mass flow of a held-thrust history reaches ``mass_kg``."""
    burnt = np.cumsum(thrust_N) * dt_s / exhaust
    k = int(np.argmax(burnt >= mass_kg))
    assert burnt[k] >= mass_kg
    before = burnt[k - 1] if k > 0 else 0.0
    return k * dt_s + (mass_kg - before) * exhaust / thrust_N[k]


def assert_engines_within_limits(result: ClosedLoopResult, problem: Problem) -> None:
    assert result.thrust_N.min() >= 0.0
    assert result.thrust_N.max() <= stage_limit_N(problem)


# --------------------------------------------------------------------------- fixtures


@pytest.fixture(scope="module")
def controller() -> control.StateSpace:
    record = Controller.from_dict(json.loads(default_controller_path().read_text()))
    return record.reduced


@pytest.fixture(scope="module")
def slew_problem() -> Problem:
    return load_problem(PROBLEMS / "paper_slew.toml")


@pytest.fixture(scope="module")
def slew_model(slew_problem: Problem) -> Model:
    return build_model(slew_problem)


@pytest.fixture(scope="module")
def slew_reference(slew_problem: Problem) -> Reference:
    return scenario_reference(slew_problem)


@pytest.fixture(scope="module")
def nominal_slew(slew_problem, slew_model, controller, slew_reference) -> ClosedLoopResult:
    return simulate_closed_loop(slew_model, controller, slew_reference)


@pytest.fixture(scope="module")
def maps(slew_problem: Problem, slew_model: Model) -> tuple[np.ndarray, np.ndarray]:
    positions, torque_map, force_map = engine_maps(slew_problem)
    # Same CubeSats in the same order as the simulation's geometry.
    np.testing.assert_allclose(
        positions, [m.position_m for m in slew_model.geometry.cubesats], atol=1e-12
    )
    return torque_map, force_map


@pytest.fixture(scope="module")
def pointing_problem() -> Problem:
    return load_problem(PROBLEMS / "paper_pointing.toml")


@pytest.fixture(scope="module")
def pointing_model(pointing_problem: Problem) -> Model:
    return build_model(pointing_problem)


@pytest.fixture(scope="module")
def hold_reference(pointing_problem: Problem) -> Reference:
    assert pointing_problem.simulation.reference == "hold"
    return scenario_reference(pointing_problem)


@pytest.fixture(scope="module")
def nominal_pointing(pointing_problem, pointing_model, controller, hold_reference):
    return simulate_closed_loop(pointing_model, controller, hold_reference)


def slew_data_with(failures: list[dict[str, Any]], duration_s: float) -> dict[str, Any]:
    """The paper's problem data with paper_slew.toml's [simulation] and the given failures."""
    with default_problem_path().open("rb") as handle:
        data = tomllib.load(handle)
    with (PROBLEMS / "paper_slew.toml").open("rb") as handle:
        slew = tomllib.load(handle)
    data["simulation"] = copy.deepcopy(slew["simulation"])
    data["simulation"]["duration_s"] = duration_s
    data["simulation"]["failures"] = failures
    return data


# CubeSats numbered from 1 as in the problem file. 19 (on +z) fires during the
# whole slew in the nominal run; 17 (+z) never does; 1 (+x, firing before and
# after 300 s) loses stage 1.
FAILURES = [
    {"time_s": FAILURE_TIME_S, "cubesat": 17},
    {"time_s": FAILURE_TIME_S, "cubesat": 19},
    {"time_s": FAILURE_TIME_S, "cubesat": 1, "stage": 1},
]
STAGE_FAILED_CUBESAT = 0


@pytest.fixture(scope="module")
def failure_problem() -> Problem:
    return problem_from_dict(slew_data_with(FAILURES, FAILURE_RUN_S), "failures")


@pytest.fixture(scope="module")
def failure_run(failure_problem, slew_model, controller, slew_reference) -> ClosedLoopResult:
    return simulate_closed_loop(
        build_model(failure_problem), controller, truncated(slew_reference, FAILURE_RUN_S)
    )


# Staging: CubeSat 19's first stage holds 4e-6 kg (it burns ~3e-5 kg in the
# nominal slew), CubeSat 10's three stages 3e-7 kg each (it burns 2.7e-6 kg).
STAGING_CUBESAT = 18
STAGING_FIRST_STAGE_KG = 4.0e-6
DROPOUT_CUBESAT = 9
DROPOUT_STAGE_KG = 3.0e-7


@pytest.fixture(scope="module")
def staging_start(slew_problem: Problem) -> PropulsionState:
    state = PropulsionState.from_problem(slew_problem)
    state.propellant_kg[STAGING_CUBESAT, 0] = STAGING_FIRST_STAGE_KG
    state.propellant_kg[DROPOUT_CUBESAT, :] = DROPOUT_STAGE_KG
    return state


@pytest.fixture(scope="module")
def staging_run(slew_problem, slew_model, controller, slew_reference, staging_start):
    return simulate_closed_loop(slew_model, controller, slew_reference, propulsion=staging_start)


# --------------------------------------------------------------------------- paper slew


def test_reference_is_180_deg_about_z(slew_problem: Problem, slew_reference: Reference) -> None:
    q = slew_reference.quaternion_BN
    times = slew_reference.time_s
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-12)
    np.testing.assert_array_equal(q[0], [1.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(q[:, 1:3], 0.0, atol=1e-15)  # about z only
    angle = 2.0 * np.arctan2(q[:, 3], q[:, 0])
    assert np.all(np.diff(angle) >= -1e-15)
    end = slew_problem.simulation.slew.duration_s
    after = times >= end - 1e-9
    np.testing.assert_allclose(
        np.abs(q[after]), np.tile([0, 0, 0, 1.0], (after.sum(), 1)), atol=1e-12
    )
    assert angle[times < end - 1.0].max() < math.pi - 1e-6  # reached at the end, not before


def test_slew_error_is_consistent_and_within_paper(
    nominal_slew: ClosedLoopResult, slew_model: Model
) -> None:
    q = nominal_slew.state[:, slew_model.layout.q]
    expected = error_vector(nominal_slew.reference_BN, q)
    np.testing.assert_allclose(nominal_slew.error_rad, expected, rtol=0, atol=1e-13)
    angle_deg = np.degrees(error_angle_rad(nominal_slew.reference_BN, q))
    assert PAPER_SLEW_MAX_ERROR.accepts(angle_deg.max())
    summary = nominal_slew.summary()
    assert summary.max_error_deg == pytest.approx(np.degrees(np.abs(expected).max()), rel=1e-12)
    assert PAPER_SLEW_MAX_ERROR.accepts(summary.max_error_deg)


def test_slew_fuel_and_bookkeeping(nominal_slew: ClosedLoopResult, slew_problem: Problem) -> None:
    fuel = fuel_from_thrust(nominal_slew, slew_problem)
    np.testing.assert_allclose(
        nominal_slew.fuel_per_cubesat_kg, fuel, rtol=1e-12, atol=propellant_atol(nominal_slew)
    )
    summary = nominal_slew.summary()
    assert summary.fuel_kg == pytest.approx(fuel.sum(), rel=1e-12)
    # The paper's figure is the fuel of the slew itself (the run goes on to settle).
    dt = nominal_slew.control_period_s
    end = slew_problem.simulation.slew.start_s + slew_problem.simulation.slew.duration_s
    inside = np.arange(len(nominal_slew.thrust_N)) < round(end / dt)
    exhaust = slew_problem.engine.isp_s * slew_problem.constants.standard_gravity_m_s2
    fuel_slew = nominal_slew.thrust_N[inside].sum() * dt / exhaust
    assert summary.fuel_slew_kg == pytest.approx(fuel_slew, rel=1e-12)
    assert PAPER_SLEW_FUEL.accepts(fuel_slew)
    # Nothing runs dry in the nominal slew: every CubeSat stays on stage 1.
    propulsion = nominal_slew.propulsion
    assert nominal_slew.events == []
    np.testing.assert_allclose(
        propulsion.firing_time_s[:, 0],
        (nominal_slew.thrust_N > 0).sum(axis=0) * nominal_slew.control_period_s,
        rtol=1e-12,
    )
    np.testing.assert_array_equal(propulsion.firing_time_s[:, 1:], 0.0)


def test_slew_thrust_torque_and_force(
    nominal_slew: ClosedLoopResult, slew_problem: Problem, maps
) -> None:
    torque_map, force_map = maps
    assert_engines_within_limits(nominal_slew, slew_problem)
    torque = nominal_slew.thrust_N @ torque_map.T
    scale = stage_limit_N(slew_problem) * np.abs(torque_map).max()  # one engine's torque
    np.testing.assert_allclose(nominal_slew.torque_Nm, torque, rtol=0, atol=1e-12 * scale)
    force = nominal_slew.thrust_N @ force_map.T
    assert np.abs(force).max() <= ALLOCATION_RTOL * stage_limit_N(slew_problem)
    np.testing.assert_allclose(nominal_slew.force_N, force, rtol=0, atol=1e-15)
    # The allocator's torque is alpha times the controller's demand.
    applied = nominal_slew.demand_Nm * nominal_slew.scale[:, None]
    deviation = np.linalg.norm(nominal_slew.torque_Nm - applied, axis=1)
    assert np.all(deviation <= ALLOCATION_RTOL * np.linalg.norm(applied, axis=1) + 1e-12 * scale)
    assert np.all(nominal_slew.scale <= 1.0) and np.all(nominal_slew.scale > 0.0)
    # The slew's bang-bang level is below the authority but the controller's
    # demand on top saturates at times: the check below has both kinds of step.
    assert 0 < np.sum(nominal_slew.scale < 1.0) < len(nominal_slew.scale) // 10


def test_slew_saturation_against_linear_programs(
    nominal_slew: ClosedLoopResult, slew_problem: Problem, maps
) -> None:
    torque_map, force_map = maps
    limits = np.full(torque_map.shape[1], stage_limit_N(slew_problem))
    saturated = np.flatnonzero(nominal_slew.scale < 1.0)
    met = np.flatnonzero(nominal_slew.scale == 1.0)
    rng = np.random.default_rng(0)
    for k in rng.choice(saturated, size=min(30, len(saturated)), replace=False):
        alpha = largest_multiple(nominal_slew.demand_Nm[k], torque_map, force_map, limits)
        # Saturated: the largest reachable multiple of the demand, direction kept.
        assert nominal_slew.scale[k] == pytest.approx(alpha, abs=ALPHA_TOL)
        reach = largest_multiple(nominal_slew.torque_Nm[k], torque_map, force_map, limits)
        assert reach >= 1.0 - ALPHA_TOL  # the applied torque is reachable
    for k in rng.choice(met, size=30, replace=False):
        alpha = largest_multiple(nominal_slew.demand_Nm[k], torque_map, force_map, limits)
        assert alpha >= 1.0 - ALPHA_TOL


def test_reproducible(nominal_slew, slew_problem, slew_model, controller, slew_reference) -> None:
    again = simulate_closed_loop(slew_model, controller, slew_reference)
    for name in ("state", "error_rad", "demand_Nm", "torque_Nm", "thrust_N", "scale"):
        np.testing.assert_array_equal(getattr(again, name), getattr(nominal_slew, name))
    np.testing.assert_array_equal(
        again.propulsion.propellant_kg, nominal_slew.propulsion.propellant_kg
    )
    assert again.events == nominal_slew.events


def test_rk4_against_cvodes(
    slew_problem, slew_model, controller, slew_reference, monkeypatch
) -> None:
    """The default RK4 (4 steps per 0.1 s) against CVODES over the first 100 s.

    CVODES is restarted every control period; each call is accurate to about
    reltol * |x| + abstol (|x| <= 1 for the quaternions that make the error),
    so over N periods the reference itself is good to N * (reltol + abstol)
    at worst (no growth: the loop is stable). That is the bound for the
    shipped settings; with CVODES tightened to 1e-13 the same bound is
    1e-10 rad (2e-5 arcsec) and then measures the RK4 error itself.
    """
    reference = truncated(slew_reference, 100.0)
    periods = len(reference.time_s) - 1
    rk4 = simulate_closed_loop(slew_model, controller, reference)
    assert np.abs(rk4.error_rad).max() > 1e-3  # the slew is under way

    options = closed_loop_module.CVODES_OPTIONS
    cvodes = LoopSettings(integrator="cvodes")
    shipped = simulate_closed_loop(slew_model, controller, reference, settings=cvodes)
    bound = periods * (options["reltol"] + options["abstol"])
    assert np.abs(rk4.error_rad - shipped.error_rad).max() <= bound

    tight = {**options, "reltol": 1e-13, "abstol": 1e-14}
    monkeypatch.setattr(closed_loop_module, "CVODES_OPTIONS", tight)
    accurate = simulate_closed_loop(slew_model, controller, reference, settings=cvodes)
    bound = periods * (tight["reltol"] + tight["abstol"])
    assert np.abs(rk4.error_rad - accurate.error_rad).max() <= bound


# --------------------------------------------------------------------------- pointing


def pointing_checks(result: ClosedLoopResult, model: Model, problem: Problem) -> float:
    """Max error [arcsec] from the logged quaternions; engines and demand within limits."""
    q = result.state[:, model.layout.q]
    np.testing.assert_allclose(
        result.error_rad, error_vector(result.reference_BN, q), rtol=0, atol=1e-13
    )
    assert result.time_s[-1] == problem.simulation.duration_s
    assert_engines_within_limits(result, problem)
    # The demand is met at every step (no saturation), to the allocator's precision.
    np.testing.assert_array_equal(result.scale, 1.0)
    deviation = np.linalg.norm(result.torque_Nm - result.demand_Nm, axis=1)
    assert np.all(deviation <= ALLOCATION_RTOL * np.linalg.norm(result.demand_Nm, axis=1) + 1e-15)
    return float(error_angle_rad(result.reference_BN, q).max() * ARCSEC_PER_RAD)


def test_pointing_nominal(nominal_pointing, pointing_model, pointing_problem, maps) -> None:
    error = pointing_checks(nominal_pointing, pointing_model, pointing_problem)
    assert PAPER_POINTING_ERROR.accepts(error)
    assert PAPER_POINTING_ERROR.accepts(nominal_pointing.summary().max_error_arcsec)
    # The disturbance is what the loop fights: 0.7 mNm amplitude per axis.
    amplitude = pointing_problem.disturbance.amplitude_mNm * 1e-3
    np.testing.assert_allclose(
        np.abs(nominal_pointing.disturbance_Nm).max(axis=0), amplitude, rtol=1e-6
    )
    torque_map, force_map = maps
    limits = np.full(torque_map.shape[1], stage_limit_N(pointing_problem))
    for k in np.linspace(0, len(nominal_pointing.scale) - 1, 12).astype(int):
        reach = largest_multiple(nominal_pointing.torque_Nm[k], torque_map, force_map, limits)
        assert reach >= 1.0 - ALPHA_TOL


def corner(model: Model, problem: Problem, signs: tuple[int, ...], angle_deg: float) -> np.ndarray:
    """Parameters at an extreme of the uncertainty set (signs: inertia x, y, z, mass, bending)."""
    u = problem.uncertainty
    nominal = dict(zip(model.parameter_names, model.nominal_parameters, strict=True))
    return model.parameters(
        inertia_scale_x=1.0 + signs[0] * u.inertia_fraction,
        inertia_scale_y=1.0 + signs[1] * u.inertia_fraction,
        inertia_scale_z=1.0 + signs[2] * u.inertia_fraction,
        mass_kg=nominal["mass_kg"] * (1.0 + signs[3] * u.mass_fraction),
        array_angle_offset_rad=math.radians(angle_deg),
        bending_frequency_scale=1.0 + signs[4] * u.bending_frequency_fraction,
    )


def corner_angles(problem: Problem) -> np.ndarray:
    """The corner array angles: evenly over the +-range (its ends are one attitude)."""
    count = problem.montecarlo.corner_array_angles
    span = problem.uncertainty.array_angle_deg
    return -span + 2.0 * span * np.arange(count) / count


DEFAULT_CORNERS = [((1, 1, 1, 1, -1), 0), ((-1, -1, -1, -1, 1), 2)]  # (signs, angle index)


@pytest.mark.parametrize(("signs", "angle_index"), DEFAULT_CORNERS)
def test_pointing_corner(
    signs, angle_index, pointing_model, pointing_problem, controller, hold_reference
) -> None:
    angle = corner_angles(pointing_problem)[angle_index]
    p = corner(pointing_model, pointing_problem, signs, angle)
    result = simulate_closed_loop(pointing_model, controller, hold_reference, parameters=p)
    np.testing.assert_array_equal(list(result.parameters.values()), p)
    assert PAPER_POINTING_ERROR.accepts(pointing_checks(result, pointing_model, pointing_problem))


@pytest.mark.slow
def test_pointing_more_corners(
    pointing_model, pointing_problem, controller, hold_reference
) -> None:
    # One corner per array angle, the other extremes drawn (seeded) from the 2^5.
    rng = np.random.default_rng(pointing_problem.montecarlo.seed)
    for angle in corner_angles(pointing_problem):
        signs = tuple(int(s) for s in rng.choice([-1, 1], size=5))
        p = corner(pointing_model, pointing_problem, signs, angle)
        result = simulate_closed_loop(pointing_model, controller, hold_reference, parameters=p)
        error = pointing_checks(result, pointing_model, pointing_problem)
        assert PAPER_POINTING_ERROR.accepts(error), (signs, angle, error)


# --------------------------------------------------------------------------- failures


def test_failures_read_from_problem(failure_problem: Problem) -> None:
    events = failure_problem.simulation.failures
    assert [(e.time_s, e.cubesat, e.stage) for e in events] == [
        (FAILURE_TIME_S, 16, None),
        (FAILURE_TIME_S, 18, None),
        (FAILURE_TIME_S, 0, 0),
    ]


def test_failed_engines_stop(
    failure_run: ClosedLoopResult, nominal_slew: ClosedLoopResult, failure_problem: Problem
) -> None:
    step = round(FAILURE_TIME_S / failure_run.control_period_s)
    assert [(e.time_s, e.text) for e in failure_run.events] == [
        (FAILURE_TIME_S, "CubeSat 17 failed"),
        (FAILURE_TIME_S, "CubeSat 19 failed"),
        (FAILURE_TIME_S, "CubeSat 1: stage 1 failed"),
    ]
    # CubeSat 1 was firing stage 1: its failure hands over to stage 2, a switch.
    assert [e.switched for e in failure_run.events] == [False, False, True]
    assert failure_run.summary().stage_switches == 1
    # Identical to the nominal run up to the failure.
    np.testing.assert_array_equal(failure_run.thrust_N[:step], nominal_slew.thrust_N[:step])
    np.testing.assert_array_equal(failure_run.state[: step + 1], nominal_slew.state[: step + 1])
    # CubeSat 19 was firing and would have gone on; after the failure it is off.
    assert failure_run.thrust_N[:step, 18].max() > 0
    assert nominal_slew.thrust_N[step : len(failure_run.thrust_N), 18].max() > 0
    np.testing.assert_array_equal(failure_run.thrust_N[step:, [16, 18]], 0.0)
    assert_engines_within_limits(failure_run, failure_problem)
    assert failure_run.propulsion.failed_cubesats[[16, 18]].all()
    assert PAPER_SLEW_MAX_ERROR.accepts(failure_run.summary().max_error_deg)


def test_failed_stage_hands_over(failure_run: ClosedLoopResult, failure_problem: Problem) -> None:
    # CubeSat 1 goes on firing on stage 2: stage 1 keeps what it had at 300 s.
    step = round(FAILURE_TIME_S / failure_run.control_period_s)
    dt = failure_run.control_period_s
    exhaust = failure_problem.engine.isp_s * failure_problem.constants.standard_gravity_m_s2
    thrust = failure_run.thrust_N[:, STAGE_FAILED_CUBESAT]
    assert thrust[:step].max() > 0 and thrust[step:].max() > 0
    used = failure_run.propulsion.fuel_used_kg[STAGE_FAILED_CUBESAT]
    atol = propellant_atol(failure_run)
    np.testing.assert_allclose(used[0], thrust[:step].sum() * dt / exhaust, rtol=1e-12, atol=atol)
    np.testing.assert_allclose(used[1], thrust[step:].sum() * dt / exhaust, rtol=1e-12, atol=atol)
    assert used[2] == 0.0
    np.testing.assert_allclose(
        failure_run.propulsion.firing_time_s[STAGE_FAILED_CUBESAT, :2],
        [(thrust[:step] > 0).sum() * dt, (thrust[step:] > 0).sum() * dt],
        rtol=1e-12,
    )


def test_the_run_records_its_authority_before_and_after_the_failures(
    failure_run: ClosedLoopResult, failure_problem: Problem, slew_model: Model
) -> None:
    geometry = slew_model.geometry
    assert failure_run.authority_time_s.tolist() == [0.0, FAILURE_TIME_S]
    alive = np.ones(len(geometry.engines), dtype=bool)
    for row, failed in zip(failure_run.authority_Nm, ((), (16, 18)), strict=True):
        alive[[e for c in failed for e in geometry.cubesats[c].engines]] = False
        expected = torque_authority(geometry, zero_net_force=True, available=alive)
        order = [f"{sign}{axis}" for axis in "xyz" for sign in "+-"]
        np.testing.assert_allclose(row, [expected[k] for k in order], rtol=1e-7)


def test_failures_change_fuel(
    failure_run: ClosedLoopResult, nominal_slew: ClosedLoopResult, failure_problem: Problem
) -> None:
    fuel = fuel_from_thrust(failure_run, failure_problem)
    np.testing.assert_allclose(
        failure_run.fuel_per_cubesat_kg, fuel, rtol=1e-12, atol=propellant_atol(failure_run)
    )
    n = len(failure_run.thrust_N)
    exhaust = failure_problem.engine.isp_s * failure_problem.constants.standard_gravity_m_s2
    nominal = nominal_slew.thrust_N[:n].sum() * nominal_slew.control_period_s / exhaust
    assert abs(fuel.sum() - nominal) > 1e-3 * nominal


def test_failed_engines_keep_the_allocator_fast(failure_run: ClosedLoopResult) -> None:
    # Nominally the slew needs ~60 point solves for 13000 steps; the region
    # reuse should not break down because an engine is gone.
    assert failure_run.point_solves < 0.1 * len(failure_run.thrust_N)


@pytest.mark.slow
def test_failures_full_slew(slew_model, controller, slew_reference) -> None:
    duration = load_problem(PROBLEMS / "paper_slew.toml").simulation.duration_s
    problem = problem_from_dict(slew_data_with(FAILURES, duration), "failures")
    result = simulate_closed_loop(build_model(problem), controller, slew_reference)
    step = round(FAILURE_TIME_S / result.control_period_s)
    np.testing.assert_array_equal(result.thrust_N[step:, [16, 18]], 0.0)
    assert PAPER_SLEW_MAX_ERROR.accepts(result.summary().max_error_deg)


# --------------------------------------------------------------------------- staging


def test_stage_runs_dry_when_predicted(
    staging_run: ClosedLoopResult, staging_start: PropulsionState, slew_problem: Problem
) -> None:
    dt = staging_run.control_period_s
    exhaust = slew_problem.engine.isp_s * slew_problem.constants.standard_gravity_m_s2
    thrust = staging_run.thrust_N[:, STAGING_CUBESAT]
    predicted = crossing_time_s(thrust, dt, exhaust, STAGING_FIRST_STAGE_KG)
    number = STAGING_CUBESAT + 1
    [time] = [
        e.time_s
        for e in staging_run.events
        if e.text == f"CubeSat {number}: stage 1 empty, stage 2 takes over"
    ]
    assert time == pytest.approx(predicted, abs=1e-9)
    # It keeps firing on stage 2, at the same limit.
    stages = staging_start.stage_thrust_N[STAGING_CUBESAT]
    assert stages[1] == stages[0]
    after = thrust[math.floor(predicted / dt) + 1 :]
    assert after.max() > 0 and after.max() <= stage_limit_N(slew_problem)
    propellant = staging_run.propulsion.propellant_kg[STAGING_CUBESAT]
    capacity = staging_start.stage_capacity_kg[STAGING_CUBESAT]
    assert propellant[0] == 0.0
    burnt = thrust.sum() * dt / exhaust
    np.testing.assert_allclose(
        capacity[1] - propellant[1], burnt - STAGING_FIRST_STAGE_KG, rtol=1e-12
    )
    assert propellant[2] == capacity[2]


def test_cubesat_drops_out_when_predicted(
    staging_run: ClosedLoopResult, slew_problem: Problem
) -> None:
    dt = staging_run.control_period_s
    exhaust = slew_problem.engine.isp_s * slew_problem.constants.standard_gravity_m_s2
    thrust = staging_run.thrust_N[:, DROPOUT_CUBESAT]
    predicted = [crossing_time_s(thrust, dt, exhaust, (i + 1) * DROPOUT_STAGE_KG) for i in range(3)]
    number = DROPOUT_CUBESAT + 1
    mine = [(e.time_s, e.text) for e in staging_run.events if e.cubesat == DROPOUT_CUBESAT]
    assert [text for _, text in mine] == [
        f"CubeSat {number}: stage 1 empty, stage 2 takes over",
        f"CubeSat {number}: stage 2 empty, stage 3 takes over",
        f"CubeSat {number}: stage 3 empty, none left",
    ]
    np.testing.assert_allclose([t for t, _ in mine], predicted, rtol=0, atol=1e-9)
    # Nothing after the step in which the last stage ran dry.
    last = math.floor(predicted[-1] / dt)
    assert last < len(thrust) - 1
    np.testing.assert_array_equal(thrust[last + 1 :], 0.0)
    assert not staging_run.propulsion.available[DROPOUT_CUBESAT]
    np.testing.assert_array_equal(staging_run.propulsion.propellant_kg[DROPOUT_CUBESAT], 0.0)
    assert staging_run.fuel_per_cubesat_kg[DROPOUT_CUBESAT] == pytest.approx(
        3 * DROPOUT_STAGE_KG, rel=1e-12
    )


def test_staging_run_still_tracks(
    staging_run: ClosedLoopResult, slew_problem: Problem, slew_model: Model
) -> None:
    assert_engines_within_limits(staging_run, slew_problem)
    q = staging_run.state[:, slew_model.layout.q]
    angle = error_angle_rad(staging_run.reference_BN, q)
    assert PAPER_SLEW_MAX_ERROR.accepts(np.degrees(angle.max()))
    times = [e.time_s for e in staging_run.events]
    assert times == sorted(times)
    assert staging_run.summary().stage_switches == 4


# --------------------------------------------------------------------------- bad input


def test_non_uniform_reference_rejected(slew_problem, slew_model, controller) -> None:
    times = np.arange(0.0, 2.0, 0.1)
    times[7] += 0.01
    reference = Reference(times, np.tile([1.0, 0, 0, 0], (len(times), 1)), None)
    with pytest.raises(SimulationError, match="uniformly"):
        simulate_closed_loop(slew_model, controller, reference)
    single = Reference(times[:1], np.array([[1.0, 0, 0, 0]]), None)
    with pytest.raises(SimulationError, match="two instants"):
        simulate_closed_loop(slew_model, controller, single)


def test_wrong_controller_rejected(slew_problem, slew_model) -> None:
    reference = sample_reference(np.arange(0.0, 1.0, 0.1))
    wrong = control.ss(-np.eye(2), np.ones((2, 2)), np.ones((3, 2)), np.zeros((3, 2)))
    with pytest.raises(SimulationError, match="3 attitude errors"):
        simulate_closed_loop(slew_model, wrong, reference)


def test_unknown_integrator_rejected(slew_problem, slew_model, controller) -> None:
    reference = sample_reference(np.arange(0.0, 1.0, 0.1))
    with pytest.raises(SimulationError, match="integrator"):
        simulate_closed_loop(
            slew_model,
            controller,
            reference,
            settings=LoopSettings(integrator="euler"),
        )
