"""The worst-case slew search: helpers against closed forms, the search against the corners."""

from __future__ import annotations

import control
import numpy as np
import pytest

from casadi_debris import load_problem
from casadi_debris.allocation import Allocator
from casadi_debris.campaigns import (
    WorstCaseSettings,
    corner_cases,
    linear_screen,
    worst_case_search,
)
from casadi_debris.campaigns import _worst_case as worst_case
from casadi_debris.campaigns._worst_case import _largest_outputs, _project, _rotation_vectors
from casadi_debris.config import default_problem_path, with_duration
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.simulation import simulate_closed_loop
from casadi_debris.workflows import load_controller

SLEW = default_problem_path().parent / "paper_slew.toml"


def test_rotation_vectors_are_continuous_through_half_a_turn() -> None:
    angles = np.linspace(0.0, np.pi + 0.2, 50)
    q = np.column_stack([np.cos(angles / 2), 0 * angles, 0 * angles, np.sin(angles / 2)])
    assert np.allclose(_rotation_vectors(q)[:, 2], angles)
    assert np.allclose(_rotation_vectors(q)[:, :2], 0.0)


def test_projection_clips_the_box_and_wraps_a_full_turn_angle() -> None:
    problem = load_problem(SLEW)
    model = build_model(problem)
    z = np.array([1.5, -2.0, 0.5, 0.0, 1.25, -1.1])
    projected = _project(model, z)
    assert projected.tolist() == [1.0, -1.0, 0.5, 0.0, -0.75, -1.0]


def _one_by_one(loops, t, inputs) -> np.ndarray:
    """python-control's forced response, one loop at a time."""
    return np.array([np.max(np.abs(control.forced_response(x, t, inputs).outputs)) for x in loops])


def test_loops_stepped_together_respond_as_forced_response_says() -> None:
    rng = np.random.default_rng(7)
    loops = [control.rss(5, 2, 3, strictly_proper=k == 1) for k in range(3)]
    t = np.linspace(2.0, 12.0, 41)
    u = rng.normal(size=(3, t.size))
    np.testing.assert_allclose(_largest_outputs(loops, t, u), _one_by_one(loops, t, u), rtol=1e-10)


def test_the_screen_of_the_papers_corners_is_their_forced_responses(monkeypatch) -> None:
    # The pointing problem: its reference is ready at once (the slew's takes seconds).
    problem = with_duration(load_problem(SLEW.with_name("paper_pointing.toml")), 100.0)
    model = build_model(problem)
    record, _ = load_controller()
    reference = scenario_reference(problem)
    corners = np.array([c.normalized for c in corner_cases(model)[::51]])
    screened = linear_screen(model, record.reduced, reference, corners)
    monkeypatch.setattr(worst_case, "_largest_outputs", _one_by_one)
    expected = linear_screen(model, record.reduced, reference, corners)
    assert np.all(expected > 0)
    np.testing.assert_allclose(screened, expected, rtol=1e-10)


def _max_error(problem, model, controller, reference, p) -> float:
    allocator = Allocator.from_problem(problem, model.geometry)
    run = simulate_closed_loop(model, controller, reference, parameters=p, allocator=allocator)
    return float(run.summary().max_error_deg)


@pytest.mark.slow
def test_search_is_at_least_as_bad_as_every_corner_of_a_reduced_set() -> None:
    problem = with_duration(load_problem(SLEW), 400.0)
    model = build_model(problem)
    record, _ = load_controller()
    reference = scenario_reference(problem)
    cases = corner_cases(model)[128:160]  # the corners at 0 deg, 142 among them
    corners = np.array([c.normalized for c in cases[::4]] + [cases[14].normalized])
    found = worst_case_search(
        model,
        record.reduced,
        reference,
        corners,
        settings=WorstCaseSettings(budget=8, screen_starts=2, seed=1),
    )
    brute = max(
        _max_error(problem, model, record.reduced, reference, c.parameters)
        for c in [*cases[::4], cases[14]]
    )
    assert found.simulations <= 8
    assert found.best.max_error_deg >= brute * (1 - 1e-9)
    again = _max_error(problem, model, record.reduced, reference, found.best.parameters)
    assert again == pytest.approx(found.best.max_error_deg, rel=1e-9)
    assert [e.index for e in found.evaluations] == list(range(found.simulations))


@pytest.mark.slow
def test_fifty_simulations_reach_the_worst_of_the_256_corners() -> None:
    problem = load_problem(SLEW)
    model = build_model(problem)
    record, _ = load_controller()
    reference = scenario_reference(problem)
    cases = corner_cases(model)
    corner_142 = _max_error(problem, model, record.reduced, reference, cases[142].parameters)
    found = worst_case_search(
        model,
        record.reduced,
        reference,
        np.array([c.normalized for c in cases]),
        settings=WorstCaseSettings(budget=50, seed=0),
    )
    assert found.simulations <= 50
    assert found.best.max_error_deg >= corner_142 * (1 - 1e-9)
