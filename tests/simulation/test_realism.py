"""Realistic sensors, delay and engines in the compiled step, against hand-computed cases.

The controller is replaced by one of zero gain, so that the torque demand is
the feed-forward input: the delay, the minimum impulse bit and the thrust ramp
then act on a known command, and their effect is computed here by hand (an
integral of the delayed or lagged command over each period).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import quad

from casadi_debris.allocation import Allocator
from casadi_debris.config import (
    Actuators,
    ControllerTiming,
    Estimation,
    Sensors,
    StarTracker,
    load_problem,
    realism_fields,
)
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.simulation import (
    DiscreteController,
    LoopSettings,
    Realism,
    StepInput,
    StepOutput,
    build_loop_step,
    draw_noise,
    engine_basis,
    simulate_closed_loop,
)
from casadi_debris.workflows import load_controller

PERIOD_S = 0.1
STEPS = 12
TORQUE_NM = np.array([0.0, 0.0, 1e-3])


@pytest.fixture(scope="module")
def paper():
    problem = load_problem("paper_pointing")
    model = build_model(problem)
    return problem, model, Allocator.from_problem(problem, model.geometry)


def _zero_controller() -> DiscreteController:
    return DiscreteController(
        np.zeros((1, 1)), np.zeros((1, 3)), np.zeros((3, 1)), np.zeros((3, 3)), PERIOD_S
    )


def _roll(problem, model, allocator, feedforward_Nm: np.ndarray) -> np.ndarray:
    """Outputs y (rows, steps) of the realistic step of ``problem`` for a feed-forward series."""
    realism = Realism.of(problem, PERIOD_S)
    assert realism is not None
    loop = build_loop_step(
        model,
        model.nominal_parameters,
        _zero_controller(),
        allocator.authority_polytope(),
        chunk_steps=STEPS,
        realism=realism,
        basis=engine_basis(allocator) if realism.engine_level else None,
    )
    t = np.arange(STEPS) * PERIOD_S
    inputs = np.zeros((loop.n_inputs, STEPS))
    inputs[StepInput.TIME_S] = t
    inputs[StepInput.REFERENCE_BN.start] = 1.0
    inputs[StepInput.FEEDFORWARD_NM] = feedforward_Nm.T
    noise = draw_noise(problem, model.geometry, t)
    inputs[StepInput.SIZE :] = realism.inputs.rows(problem, noise, PERIOD_S, 0, STEPS)
    z0 = np.concatenate(
        [model.initial_state(), np.zeros(1), realism.initial_aux(problem, np.array([1.0, 0, 0, 0]))]
    )
    _, y = loop.roll(z0, inputs, model.nominal_parameters)
    return y


def _step_command(on_from: int) -> np.ndarray:
    command = np.zeros((STEPS, 3))
    command[on_from:] = TORQUE_NM
    return command


@pytest.mark.parametrize(
    ("controller_s", "latency_s"), [(0.25, 0.0), (0.15, 0.1), (0.0, 0.25), (0.2, 0.0)]
)
def test_delay_shifts_the_torque_by_hand(paper, controller_s, latency_s) -> None:
    problem, model, allocator = paper
    problem = dataclasses.replace(
        problem,
        controller=ControllerTiming(delay_s=controller_s),
        actuators=Actuators(latency_s=latency_s),
    )
    y = _roll(problem, model, allocator, _step_command(3))
    delay = controller_s + latency_s
    on = 3 * PERIOD_S + delay  # the command switched on at 0.3 s, acting from 0.3 s + delay
    for k in range(STEPS):
        end = (k + 1) * PERIOD_S
        fraction = min(max((end - on) / PERIOD_S, 0.0), 1.0)
        np.testing.assert_allclose(
            y[StepOutput.APPLIED_NM, k], fraction * TORQUE_NM, rtol=1e-9, atol=1e-15
        )


def _allocated(allocator: Allocator, torque: np.ndarray) -> np.ndarray:
    return np.asarray(allocator.allocate(torque).thrust_N)


def test_minimum_impulse_bit_by_hand(paper) -> None:
    problem, model, allocator = paper
    # A torque about two axes: the engines of each get different thrusts.
    torque = np.array([0.4e-3, 0.0, 1e-3])
    thrust = _allocated(allocator, [torque[0], 0, 0]) + _allocated(allocator, [0, 0, torque[2]])
    impulses_uNs = np.unique(np.round(thrust[thrust > 0] * PERIOD_S * 1e6, 9))
    assert len(impulses_uNs) >= 2
    threshold = float(np.mean(impulses_uNs[:2]))  # between the two smallest impulses
    problem = dataclasses.replace(problem, actuators=Actuators(minimum_impulse_bit_uNs=threshold))
    y = _roll(problem, model, allocator, np.tile(torque, (STEPS, 1)))
    fired = np.where(thrust * PERIOD_S * 1e6 >= threshold, thrust, 0.0)
    for k in range(STEPS):
        change = y[StepOutput.THRUST_CHANGE_START :, k]
        np.testing.assert_allclose(change, fired - thrust, rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(
            y[StepOutput.APPLIED_NM, k], model.geometry.torque_map @ fired, rtol=1e-9, atol=1e-15
        )
    assert np.abs(y[StepOutput.APPLIED_NM, 0] - torque).max() > 1e-5  # it made a difference
    # Above every engine's impulse: nothing fires.
    silent = dataclasses.replace(
        problem, actuators=Actuators(minimum_impulse_bit_uNs=float(impulses_uNs.max()) * 1.01)
    )
    y = _roll(silent, model, allocator, np.tile(torque, (STEPS, 1)))
    np.testing.assert_allclose(y[StepOutput.APPLIED_NM], 0.0, atol=1e-15)
    np.testing.assert_allclose(y[StepOutput.THRUST_CHANGE_START :, 0], -thrust, atol=1e-15)


def test_thrust_ramp_by_hand(paper) -> None:
    problem, model, allocator = paper
    lag = 0.3
    problem = dataclasses.replace(problem, actuators=Actuators(ramp_time_constant_s=lag))
    y = _roll(problem, model, allocator, _step_command(0))
    target = _allocated(allocator, TORQUE_NM)
    engine = int(np.argmax(target))
    for k in range(STEPS):
        mean, _ = quad(lambda t: 1.0 - math.exp(-t / lag), k * PERIOD_S, (k + 1) * PERIOD_S)
        expected = target[engine] * mean / PERIOD_S
        fired = target[engine] + y[StepOutput.THRUST_CHANGE_START + engine, k]
        assert fired == pytest.approx(expected, rel=1e-9)


def test_defaults_leave_the_paper_loop(paper) -> None:
    problem, _, _ = paper
    for name in ("paper", "paper_slew", "paper_pointing", "paper_environment"):
        assert Realism.of(load_problem(name), PERIOD_S) is None
    explicit = dataclasses.replace(
        problem, sensors=Sensors(), estimation=Estimation(), actuators=Actuators()
    )
    assert Realism.of(explicit, PERIOD_S) is None


@pytest.fixture(scope="module")
def short_runs(paper):
    problem, _, _ = paper
    record, _ = load_controller()
    short = dataclasses.replace(
        problem, simulation=dataclasses.replace(problem.simulation, duration_s=20.0)
    )
    held = dataclasses.replace(
        short, sensors=Sensors(StarTracker(noise_arcsec=5.0, update_rate_hz=2.0), seed=4)
    )
    reference = scenario_reference(short)
    realistic = load_problem("paper_realistic")
    everything = dataclasses.replace(short, **realism_fields(realistic))
    held_model = build_model(held)
    return {
        "held": simulate_closed_loop(held_model, record.reduced, reference),
        "held_again": simulate_closed_loop(held_model, record.reduced, reference),
        "other_seed": simulate_closed_loop(held_model, record.reduced, reference, noise_seed=9),
        "everything": simulate_closed_loop(build_model(everything), record.reduced, reference),
    }


def test_readings_are_held_between_updates(short_runs) -> None:
    run = short_runs["held"]
    measured = run.measured_error_rad
    changes = np.flatnonzero(np.any(np.diff(measured, axis=0) != 0.0, axis=1)) + 1
    assert set(changes) <= set(range(0, len(measured), 5))  # 2 Hz at 10 Hz
    assert len(changes) >= len(measured) // 5 - 1
    assert run.summary().noise_seed == 4


def test_noise_is_seeded(short_runs) -> None:
    np.testing.assert_array_equal(short_runs["held"].state, short_runs["held_again"].state)
    assert not np.array_equal(short_runs["held"].state, short_runs["other_seed"].state)
    assert short_runs["other_seed"].noise_seed == 9


def test_engines_books_balance(short_runs) -> None:
    run = short_runs["everything"]
    exhaust = run.propulsion.exhaust_velocity_m_s
    burnt = (run.thrust_N * run.control_period_s / exhaust).sum()
    assert run.fuel_per_engine_kg.sum() == pytest.approx(burnt, rel=1e-9)
    assert np.abs(run.force_N).max() > 0.0  # misaligned engines push the body
    summary = run.summary()
    assert summary.max_estimation_error_arcsec is not None
    assert summary.max_estimation_error_arcsec < 200.0


def test_engines_without_effects_fly_the_ideal_loop(paper) -> None:
    # Engine-level books with no effect (a minimum impulse no engine is below):
    # the same torques, states and fuel as the paper's loop.
    problem, _, _ = paper
    record, _ = load_controller()
    short = dataclasses.replace(
        problem, simulation=dataclasses.replace(problem.simulation, duration_s=20.0)
    )
    reference = scenario_reference(short)
    ideal = simulate_closed_loop(build_model(short), record.reduced, reference)
    books = dataclasses.replace(short, actuators=Actuators(minimum_impulse_bit_uNs=1e-9))
    engines = simulate_closed_loop(build_model(books), record.reduced, reference)
    np.testing.assert_allclose(engines.state, ideal.state, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(engines.thrust_N, ideal.thrust_N, rtol=1e-9, atol=1e-12)


@pytest.mark.slow
def test_compiled_realistic_step_matches_the_virtual_machine(paper) -> None:
    # Every effect at once, as C and on CasADi's virtual machine (a compile of tens of seconds).
    problem, _, _ = paper
    real = load_problem("paper_realistic")
    problem = dataclasses.replace(problem, **realism_fields(real))
    record, _ = load_controller()
    short = dataclasses.replace(
        problem, simulation=dataclasses.replace(problem.simulation, duration_s=30.0)
    )
    reference = scenario_reference(short)
    short_model = build_model(short)
    machine = simulate_closed_loop(short_model, record.reduced, reference)
    compiled = simulate_closed_loop(
        short_model, record.reduced, reference, settings=LoopSettings(jit=True)
    )
    if not compiled.compiled_step:
        pytest.skip("no C compiler")
    np.testing.assert_allclose(compiled.state, machine.state, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(compiled.thrust_N, machine.thrust_N, rtol=1e-9, atol=1e-12)


def test_series_carry_the_estimation_error(short_runs) -> None:
    from casadi_debris.report import series_columns

    run = short_runs["everything"]
    columns = series_columns(run)
    truth_told = (run.measured_error_rad - run.error_rad[:-1]) * 180 / math.pi * 3600
    np.testing.assert_allclose(columns["estimation_error_z_arcsec"][:-1], truth_told[:, 2])
    ideal = dataclasses.replace(run, noise_seed=None)  # as the paper's loop records it
    assert not any(name.startswith("estimation") for name in series_columns(ideal))
