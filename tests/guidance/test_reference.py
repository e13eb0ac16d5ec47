"""The reference the loop follows: Hermite-sampled slew and its feed-forward torque."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from casadi_debris.config import default_problem_path, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.errors import ProblemFileError
from casadi_debris.guidance import generate_slew, sample_reference, scenario_reference

SLEW_PROBLEM = default_problem_path().parent / "paper_slew.toml"


@pytest.fixture(scope="module")
def slew_problem():
    return load_problem(SLEW_PROBLEM)


def test_reference_quaternion_follows_the_bang_bang_angle(slew_problem) -> None:
    """psi(t) of a rest-to-rest bang-bang: a t^2 / 2 up to half time (the coast is empty)."""
    reference = scenario_reference(slew_problem)
    settings = reference.slew.settings
    acceleration = settings["acceleration_rad_s2"]
    half = reference.slew.duration_s / 2
    t = reference.time_s
    early = t < half
    expected = 0.5 * acceleration * t[early] ** 2
    angle = 2 * np.arctan2(reference.quaternion_BN[early, 3], reference.quaternion_BN[early, 0])
    assert np.abs(angle - expected).max() < 1e-9
    final = reference.quaternion_BN[-1]
    assert abs(abs(final[3]) - 1.0) < 1e-12  # 180 deg about z


def test_feedforward_is_the_rigid_torque_of_the_profile(slew_problem) -> None:
    """During acceleration the profile's torque is J e alpha + omega^2 e x J e (e = z)."""
    period = 1.0 / slew_problem.simulation.control_rate_hz
    times = period * np.arange(13001)
    slew = generate_slew(slew_problem, slew_problem.simulation.slew, 1.0)
    reference = sample_reference(times, slew, feedforward=True)
    model = build_model(slew_problem, modes=[])
    inertia = np.asarray(model.rigid_inertia(model.nominal_parameters))
    axis = np.array([0.0, 0.0, 1.0])
    alpha = slew.settings["acceleration_rad_s2"]
    k = int(100.0 / period)  # 100 s into the acceleration
    rate = alpha * times[k]
    expected = inertia @ axis * alpha + rate**2 * np.cross(axis, inertia @ axis)
    assert np.allclose(reference.feedforward_Nm[k], expected, rtol=1e-9, atol=1e-15)
    assert np.all(reference.feedforward_Nm[times > slew.duration_s + period] == 0.0)
    no_feedforward = sample_reference(times, slew)
    assert no_feedforward.feedforward_Nm is None


def test_feedforward_is_read_from_the_problem_file(tmp_path) -> None:
    path = tmp_path / "ff.toml"
    path.write_text(
        f'extends = "{SLEW_PROBLEM}"\nname = "ff"\n[simulation.slew]\naxis = "z"\n'
        "angle_deg = 180.0\nfeedforward = true\n"
    )
    problem = load_problem(path)
    assert problem.simulation.slew.feedforward is True
    reference = scenario_reference(problem)
    assert reference.feedforward_Nm.shape == (len(reference.time_s), 3)
    assert math.isclose(problem.simulation.slew.duration_s, 1228.0)


@pytest.mark.parametrize(
    ("table", "key"),
    [
        ('[simulation.slew]\naxis = "z"\nangle_deg = 180.0\nfeedforward = "yes"\n', "feedforward"),
        ('[simulation.slew]\naxis = "q"\nangle_deg = 180.0\n', "simulation.slew.axis"),
        ('[simulation.slew]\naxis = "z"\nangle_deg = 180.0\nthrusters = true\n', "thrusters"),
        ("[simulation]\ncontrol_rate_hz = 0.0\n", "simulation.control_rate_hz"),
        ("[[simulation.failures]]\ntime_s = 1.0\ncubesat = 25\n", "cubesat"),
        ("[montecarlo]\ncorner_array_angles = 0\n", "montecarlo.corner_array_angles"),
    ],
)
def test_bad_simulation_tables_name_the_key(tmp_path, table: str, key: str) -> None:
    from casadi_debris.errors import ProblemFileError

    path = tmp_path / "bad.toml"
    path.write_text(f'extends = "{SLEW_PROBLEM}"\nname = "bad"\n{table}')
    with pytest.raises(ProblemFileError, match=key):
        load_problem(path)


# The time-optimal minimum is solved by default by the slew command's too-short deadline
# (tests/slews/test_flexible.py); here under -m slow.
@pytest.mark.parametrize(
    "method", ["bang-bang", pytest.param("time-optimal", marks=pytest.mark.slow)]
)
def test_a_slew_shorter_than_possible_names_its_duration(tmp_path, method: str) -> None:
    path = tmp_path / "fast.toml"
    path.write_text(
        f'extends = "{default_problem_path().parent / "paper_slew.toml"}"\n'
        f'[simulation.slew]\nmethod = "{method}"\nduration_s = 500.0\n'
    )
    problem = load_problem(path)
    with pytest.raises(ProblemFileError, match=r"simulation\.slew\.duration_s: .*minimum is 9"):
        generate_slew(problem, problem.simulation.slew, 1.0)


@pytest.mark.slow
def test_a_time_optimal_slew_within_its_deadline_is_the_fastest(tmp_path) -> None:
    path = tmp_path / "deadline.toml"
    path.write_text(
        f'extends = "{default_problem_path().parent / "paper_slew.toml"}"\n'
        '[simulation.slew]\nmethod = "time-optimal"\nduration_s = 2000.0\n'
    )
    problem = load_problem(path)
    with_deadline = generate_slew(problem, problem.simulation.slew, 1.0)
    free = generate_slew(problem, replace(problem.simulation.slew, duration_s=None), 1.0)
    assert with_deadline.duration_s == pytest.approx(free.duration_s, rel=1e-9)
    assert with_deadline.duration_s < 2000.0
