"""A burn flown while pointing, checked against independent computations: the
rocket equation and the force's impulse, a least-fuel LP of the force alone, the
allocated thrusts' wrench, and the stages' depletion time."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import linprog

from casadi_debris import load_problem
from casadi_debris.allocation import Allocator, PropulsionState
from casadi_debris.dynamics import build_model
from casadi_debris.environment import CircularOrbit
from casadi_debris.geometry import build_geometry
from casadi_debris.guidance import (
    BurnPlan,
    burn_offset,
    strongest_axis,
    torque_free_thrust_N,
)
from casadi_debris.simulation import SimulationError
from casadi_debris.simulation.burn import burn_summary, first_stage_left, simulate_burn
from casadi_debris.workflows import controller_for

BURN_S = 40.0
STAGE_LEFT_S = 5.0


@pytest.fixture(scope="module")
def flown():
    problem = load_problem()
    model = build_model(problem)
    controller = controller_for(problem)[0].reduced
    plan = BurnPlan("retrograde", strongest_axis(problem), BURN_S)
    engines = first_stage_left(PropulsionState.from_problem(problem), STAGE_LEFT_S)
    run = simulate_burn(model, controller, plan, propulsion=engines, jit=True)
    allocator = Allocator.from_problem(problem)
    summary, series = burn_summary(problem, run, allocator)
    return problem, run, summary, series, allocator


def test_the_thrusts_deliver_the_force_and_the_applied_torque(flown) -> None:
    _, run, _, _, allocator = flown
    result = run.result
    phi = torque_free_thrust_N(allocator, run.plan.body_axis) * run.plan.body_axis
    force = result.thrust_N @ allocator.force_map.T
    torque = result.thrust_N @ allocator.torque_map.T
    assert np.abs(force - phi).max() <= 1e-9 * np.linalg.norm(phi)
    assert np.abs(torque - result.torque_Nm).max() <= 1e-12
    applied = result.demand_Nm * np.minimum(result.scale, 1.0)[:, None]
    assert np.abs(torque - applied).max() <= 1e-9 * np.abs(applied).max()
    assert np.all(result.thrust_N >= 0.0)


def test_the_paper_swarm_pushes_with_a_whole_face(flown) -> None:
    # Four CubeSats of 0.64 mN on the face whose normal is the strongest axis.
    _, run, summary, _, _ = flown
    assert summary.thrust_mN == pytest.approx(4 * 0.64, rel=1e-9)
    assert np.isclose(abs(run.plan.body_axis) @ [0.0, 1.0, 0.0], 1.0)


def test_delta_v_against_the_impulse_the_frame_turn_and_the_rocket_equation(flown) -> None:
    problem, _run, summary, _, _ = flown
    mass = build_geometry(problem).mass_kg
    thrust = summary.thrust_mN * 1e-3
    assert summary.dv_m_s == pytest.approx(thrust * BURN_S / mass, rel=1e-9)
    # The body turns with the LVLH frame at the orbit rate n: the inertial velocity change
    # is the chord of the arc, T t / M * sin(n t / 2) / (n t / 2).
    turn = CircularOrbit.from_problem(problem).mean_motion_rad_s * BURN_S
    chord = thrust * BURN_S / mass * math.sin(turn / 2) / (turn / 2)
    assert summary.dv_plant_m_s == pytest.approx(chord, rel=1e-6)
    assert summary.dv_force_inertial_m_s == pytest.approx(summary.dv_plant_m_s, rel=1e-6)
    assert summary.dv_along_m_s == pytest.approx(summary.dv_m_s, rel=1e-8)
    c = problem.engines[0].isp_s * problem.constants.standard_gravity_m_s2
    propellant = thrust * BURN_S / c
    assert summary.dv_rocket_m_s == pytest.approx(c * math.log(mass / (mass - propellant)))
    assert summary.dv_rocket_m_s - summary.dv_m_s == pytest.approx(
        summary.dv_m_s * propellant / (2 * mass), rel=1e-2
    )


def test_the_propellant_split_adds_up_and_matches_a_least_fuel_lp(flown) -> None:
    _problem, run, summary, series, allocator = flown
    result = run.result
    burnt = float((result.fuel_start_kg - result.propulsion.propellant_kg).sum())
    assert summary.fuel_dv_kg + summary.fuel_attitude_kg == pytest.approx(burnt, rel=1e-9)
    assert series.fuel_dv_kg[-1] + series.fuel_attitude_kg[-1] == pytest.approx(burnt, rel=1e-9)
    assert summary.fuel_attitude_kg > 0.0
    # The force alone at least fuel, by HiGHS on the engines' maps.
    c = result.propulsion.exhaust_velocity_m_s
    phi = torque_free_thrust_N(allocator, run.plan.body_axis) * run.plan.body_axis
    lp = linprog(
        1.0 / c,
        A_eq=np.vstack([allocator.torque_map, allocator.force_map]),
        b_eq=np.concatenate([np.zeros(3), phi]),
        bounds=[(0.0, f) for f in allocator.max_thrust_N],
        method="highs",
    )
    assert lp.status == 0
    assert summary.fuel_dv_kg == pytest.approx(lp.fun * BURN_S, rel=1e-6)
    assert summary.fuel_dv_kg >= summary.fuel_dv_bound_kg * (1 - 1e-12)


def test_stages_switch_when_their_propellant_runs_out(flown) -> None:
    _, run, summary, _, _ = flown
    switches = [e for e in summary.run.events if e.stage_switch]
    assert summary.run.stage_switches == len(switches) >= 4
    for event in switches:
        assert event.kind == "stage_depleted" and (event.stage, event.next_stage) == (1, 2)
    # The face's engines fire at full thrust from the start: dry after STAGE_LEFT_S.
    first = sorted(e.time_s for e in switches)[:4]
    assert first == pytest.approx([STAGE_LEFT_S] * 4, abs=run.result.control_period_s)
    # The next stage took over at the same thrust: the force never dropped.
    assert np.linalg.norm(run.result.force_N, axis=1).min() == pytest.approx(
        summary.thrust_mN * 1e-3, rel=1e-9
    )


def test_the_thrust_axis_holds_its_direction_within_the_requirement(flown) -> None:
    _, run, summary, _, _ = flown
    assert run.pointing_error_rad[0] == pytest.approx(0.0, abs=1e-9)
    assert summary.pointing_max_arcsec < summary.pointing_requirement_arcsec
    assert summary.meets_pointing
    # The thrust axis error never exceeds the attitude error (a single axis's share of it)
    # by more than round-off.
    attitude = np.linalg.norm(run.result.error_rad, axis=1)
    assert np.all(run.pointing_error_rad <= attitude + 1e-9)


def test_the_offset_puts_the_axis_on_the_direction() -> None:
    from casadi_debris.dynamics import quaternion_to_rotation

    rng = np.random.default_rng(3)
    for _ in range(5):
        a, d = rng.normal(size=3), rng.normal(size=3)
        a, d = a / np.linalg.norm(a), d / np.linalg.norm(d)
        q = burn_offset(a, d)
        assert quaternion_to_rotation(q[None, :]).apply(a)[0] == pytest.approx(d, abs=1e-12)


def test_bad_plans_name_their_field() -> None:
    axis = np.array([0.0, -1.0, 0.0])
    cases = [
        ({"direction": "up"}, "direction"),
        ({"body_axis": np.zeros(3)}, "body_axis"),
        ({"duration_s": -1.0}, "duration_s"),
        ({"thrust_fraction": 1.5}, "thrust_fraction"),
        ({"thrust_N": float("nan")}, "thrust_mN"),
    ]
    for change, field in cases:
        arguments = {"direction": "retrograde", "body_axis": axis, "duration_s": 10.0, **change}
        with pytest.raises(SimulationError, match=field):
            BurnPlan(**arguments)


def test_a_thrust_beyond_the_engines_is_refused() -> None:
    problem = load_problem()
    model = build_model(problem)
    controller = controller_for(problem)[0].reduced
    plan = BurnPlan("prograde", strongest_axis(problem), 1.0, thrust_N=0.01)
    with pytest.raises(SimulationError, match="thrust_mN"):
        simulate_burn(model, controller, plan)


def test_a_burn_segment_fires_only_in_its_window(tmp_path) -> None:
    """Flown by ``simulate`` from the problem file: zero net force while the body joins the
    frame, the plan's force from ``blend_s`` on, and the allocation exact throughout."""
    from casadi_debris.allocation import Allocator
    from casadi_debris.guidance import scenario_reference
    from casadi_debris.simulation import LoopSettings, simulate_closed_loop

    text = (
        'extends = "paper.toml"\nname = "burn_window"\n[simulation]\nduration_s = 120.0\n'
        'reference = "sequence"\n[[simulation.segments]]\nkind = "burn"\n'
        'direction = "normal"\nthrust_mN = 1.0\nblend_s = 40.0\n'
    )
    path = tmp_path / "burn.toml"
    path.write_text(text)
    problem = load_problem(path)
    model = build_model(problem)
    controller = controller_for(problem)[0].reduced
    reference = scenario_reference(problem)
    assert [p.kind for p in reference.pieces] == ["burn"]
    assert reference.pieces[0].firing_s == (40.0, 120.0)
    result = simulate_closed_loop(model, controller, reference, settings=LoopSettings(jit=True))
    allocator = Allocator.from_problem(problem)
    force = result.thrust_N @ allocator.force_map.T
    firing = result.time_s[:-1] >= 40.0 - 1e-9
    axis = np.array(strongest_axis(problem))
    assert np.abs(force[~firing]).max() <= 1e-15
    assert np.abs(force[firing] - 1e-3 * axis).max() <= 1e-12
    assert result.allocation_residual_Nm <= 1e-12


def test_the_force_through_the_centre_of_gravity_leaves_the_pointing_alone(flown) -> None:
    """The same burn at a negligible thrust points the same to far below an arcsec: the
    force reaches the attitude only through the arrays' translational participation."""
    problem, run, _, _, _ = flown
    model = build_model(problem)
    controller = controller_for(problem)[0].reduced
    faint = BurnPlan("retrograde", run.plan.body_axis, BURN_S, thrust_N=1e-12)
    engines = first_stage_left(PropulsionState.from_problem(problem), STAGE_LEFT_S)
    other = simulate_burn(model, controller, faint, propulsion=engines, jit=True)
    difference = np.abs(run.pointing_error_rad - other.pointing_error_rad).max()
    assert difference * 206264.8 < 1e-3
    assert np.abs(other.result.force_N).max() <= 1.001e-12  # the faint thrust itself
