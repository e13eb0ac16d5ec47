"""The closed-form modal response, checked against independent computations: the poles
of the attitude plant linearised by another route (model.linearize), and the energy the
arrays hold after piecewise-constant inputs integrated by CVODES on the full nonlinear
flexible model."""

from __future__ import annotations

import numpy as np
import pytest

from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, build_model, linearize
from casadi_debris.slews import (
    ModalResponse,
    modal_response,
    simulate_open_loop,
    vibration_energy,
    zoh_input_function,
)


@pytest.fixture(scope="module")
def flexible(problem: Problem) -> Model:
    return build_model(problem, "all")


@pytest.fixture(scope="module")
def response(flexible: Model) -> ModalResponse:
    return modal_response(flexible, flexible.nominal_parameters)


def random_inputs(seed: int, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Interval lengths (s) and model inputs (9 x count): torque ~ mNm, force ~ mN."""
    rng = np.random.default_rng(seed)
    steps = rng.uniform(0.05, 3.0, count)
    inputs = np.zeros((9, count))
    inputs[0:3] = rng.normal(scale=1e-3, size=(3, count))
    inputs[6:9] = rng.normal(scale=1e-3, size=(3, count))
    return steps, inputs


def test_eigenvalues_are_the_oscillatory_poles_of_the_attitude_plant(
    flexible: Model, response: ModalResponse
) -> None:
    poles = np.linalg.eigvals(linearize(flexible).A)
    oscillatory = np.sort_complex(poles[poles.imag > 1e-9])
    assert len(oscillatory) == flexible.layout.n_eta
    assert np.sort_complex(response.eigenvalues) == pytest.approx(oscillatory, rel=1e-9)


def test_energy_form_is_positive_definite(response: ModalResponse) -> None:
    form = response.energy_form
    assert form == pytest.approx(form.T, abs=1e-12 * np.abs(form).max())
    assert np.linalg.eigvalsh(form).min() > 0.0


@pytest.mark.parametrize("seed", [0, 1])
def test_energy_after_held_inputs_matches_the_nonlinear_model(
    flexible: Model, response: ModalResponse, seed: int
) -> None:
    steps, inputs = random_inputs(seed, 30)
    real, imag = response.final_coordinates(steps, inputs)
    predicted = float(response.energy(real, imag))

    knots = np.concatenate([[0.0], np.cumsum(steps)])
    drive = zoh_input_function(knots, inputs[0:3].T, inputs[6:9].T)
    start = flexible.initial_state(np.array([1.0, 0.0, 0.0, 0.0]))
    states = simulate_open_loop(flexible, drive, knots, start, flexible.nominal_parameters)
    integrated = vibration_energy(flexible, states[-1], flexible.nominal_parameters)
    assert integrated > 0.0
    # The rest is the rate products the linear modes leave out (rates ~1e-5 rad/s here).
    assert predicted == pytest.approx(integrated, rel=1e-4)


def test_a_step_split_in_two_is_the_same_step(response: ModalResponse) -> None:
    steps, inputs = random_inputs(2, 5)
    split_steps = np.concatenate([steps[:2], [steps[2] * 0.3, steps[2] * 0.7], steps[3:]])
    split_inputs = np.hstack([inputs[:, :3], inputs[:, 2:]])
    whole = np.concatenate(response.final_coordinates(steps, inputs))
    split = np.concatenate(response.final_coordinates(split_steps, split_inputs))
    assert split == pytest.approx(whole, rel=1e-10, abs=1e-12 * np.abs(whole).max())


def test_a_rigid_model_has_no_modal_response(problem: Problem) -> None:
    rigid = build_model(problem, modes=[])
    with pytest.raises(ValueError, match="no oscillatory"):
        modal_response(rigid, rigid.nominal_parameters)
