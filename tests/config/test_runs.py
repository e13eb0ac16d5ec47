"""A run's length: the checks of a problem file also bound a duration given later."""

from __future__ import annotations

import math

import pytest

from casadi_debris.config import limits, load_problem, run_length_violation, with_duration
from casadi_debris.errors import ProblemFileError


def test_with_duration_keeps_everything_else() -> None:
    problem = load_problem()
    shorter = with_duration(problem, 12.5)
    assert shorter.simulation.duration_s == 12.5
    assert shorter.simulation.control_rate_hz == problem.simulation.control_rate_hz
    assert shorter.hub is problem.hub and shorter.sha256 == problem.sha256


@pytest.mark.parametrize(
    ("duration_s", "words"),
    [
        (0.05, "control periods; a run holds 1 to"),
        (2e5, "is 2e\\+06 control periods"),
        (2e7, "must be at most"),
        (-1.0, "must be positive"),
        (math.nan, "must be finite"),
    ],
)
def test_with_duration_refuses_what_a_file_could_not_say(duration_s: float, words: str) -> None:
    with pytest.raises(ProblemFileError, match=f"^--duration-s: .*{words}"):
        with_duration(load_problem(), duration_s, field="--duration-s")


def test_run_length_bounds_are_those_of_the_limits() -> None:
    periods = limits.MAX_CONTROL_PERIODS
    assert run_length_violation(periods / 10.0, 10.0, 1) is None
    assert run_length_violation(periods / 10.0 * 1.001, 10.0, 1)[0] == "duration_s"
    steps = limits.MAX_INTEGRATION_STEPS // periods
    assert run_length_violation(periods / 10.0, 10.0, steps) is None
    assert run_length_violation(periods / 10.0, 10.0, steps + 1)[0] == "integrator_steps"
