"""Bandwidth and roll-off derived from the body, against the rules computed here."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linprog

from casadi_debris import load_problem
from casadi_debris.config import default_problem_path
from casadi_debris.errors import SynthesisError
from casadi_debris.geometry import build_geometry
from casadi_debris.robust.requirements import body_weights, is_papers_body

GALLERY = default_problem_path().parent / "gallery"
TEST_PROBLEMS = Path(__file__).parents[1] / "problems"


def _weakest_authority_Nm(problem) -> np.ndarray:
    """min(+, -) pure torque per axis with zero net force: an LP of the test's own."""
    geometry = build_geometry(problem)
    limits = np.array([e.max_thrust_N for e in geometry.engines])
    out = []
    for axis in range(3):
        others = [a for a in range(3) if a != axis]
        both = []
        for sign in (1.0, -1.0):
            result = linprog(
                -sign * geometry.torque_map[axis],
                A_eq=np.vstack([geometry.torque_map[others], geometry.force_map]),
                b_eq=np.zeros(5),
                bounds=list(zip(np.zeros_like(limits), limits, strict=True)),
            )
            both.append(-result.fun)
        out.append(min(both))
    return np.array(out)


def _hold_by_hand(problem) -> np.ndarray:
    inertia = np.diag(build_geometry(problem).inertia_total_kgm2)
    spare = _weakest_authority_Nm(problem) - np.abs(problem.disturbance.amplitude_mNm) * 1e-3
    return np.sqrt(spare / (inertia * math.radians(problem.requirements.slew_error_deg)))


def test_the_papers_body_keeps_the_papers_hand_tuned_weights():
    problem = load_problem()
    weights = body_weights(problem)
    assert is_papers_body(problem)
    assert (weights.bandwidth_rad_s, weights.rolloff_rad_s) == (0.028, 3.75)
    assert weights.figures.bandwidth_from == weights.figures.rolloff_from == "paper"
    # What the rules would give there, beside the paper's 0.028 and 3.75.
    derived = body_weights(problem, "derived")
    assert derived.bandwidth_rad_s == pytest.approx(_hold_by_hand(problem).min(), rel=1e-6)
    assert derived.rolloff_rad_s == pytest.approx(0.8 * 5.6 / 1.2, rel=1e-12)
    assert 0.5 < derived.bandwidth_rad_s / 0.028 < 0.7  # 0.0167: pitch binds


def test_inherited_weights_on_another_body_are_derived_from_it():
    problem = load_problem(TEST_PROBLEMS / "large_single_array.toml")
    assert problem.weights.closed_loop_bandwidth_rad_s == 0.028  # inherited from the paper
    weights = body_weights(problem)
    hold = _hold_by_hand(problem)
    assert weights.figures.bandwidth_from == weights.figures.rolloff_from == "derived"
    np.testing.assert_allclose(weights.figures.hold_bandwidth_rad_s, hold, rtol=1e-6)
    assert weights.bandwidth_rad_s == pytest.approx(hold.min(), rel=1e-6)
    # Below the array's first mode (1.2 rad/s, 20 % low in the uncertainty set).
    assert weights.rolloff_rad_s == pytest.approx(0.8 * 1.2 / 1.2, rel=1e-12)
    assert weights.bandwidth_rad_s < 0.028 / 4


def test_a_rigid_body_rolls_off_below_its_sensor_and_sampling():
    problem = load_problem(GALLERY / "rigid_no_arrays.toml")
    weights = body_weights(problem)
    assert weights.figures.first_mode_rad_s is None
    expected = 0.1 * min(problem.sensor.star_tracker_bandwidth_rad_s, math.pi * 10.0)
    assert weights.rolloff_rad_s == pytest.approx(expected, rel=1e-12)


def test_a_weight_the_problem_sets_itself_is_kept(tmp_path: Path):
    path = tmp_path / "own.toml"
    path.write_text(
        f'extends = "{(TEST_PROBLEMS / "large_single_array.toml").as_posix()}"\n'
        'name = "own"\n[weights]\nclosed_loop_bandwidth_rad_s = 0.004\n'
    )
    weights = body_weights(load_problem(path))
    assert weights.bandwidth_rad_s == 0.004 and weights.figures.bandwidth_from == "problem"
    assert weights.figures.rolloff_from == "derived"
    as_given = body_weights(load_problem(path), "problem")
    assert as_given.rolloff_rad_s == 3.75 and as_given.figures.rolloff_from == "problem"
    # The paper's roll-off on a body whose first mode is 1.2 rad/s (0.96 in the set): said.
    warning = as_given.inherited_warning(papers_body=False)
    assert warning is not None and "above the first mode (0.96 rad/s)" in warning
    assert "bandwidth" not in warning  # 0.004 is the problem's own, not the paper's
    assert body_weights(load_problem(), "problem").inherited_warning(papers_body=True) is None


def test_the_papers_bandwidth_on_a_heavier_body_is_said_to_ask_too_much_torque():
    weights = body_weights(load_problem(TEST_PROBLEMS / "large_single_array.toml"), "problem")
    warning = weights.inherited_warning(papers_body=False)
    ratio = (0.028 / weights.figures.derived_bandwidth_rad_s) ** 2
    assert warning is not None and f"asks {ratio:.3g} times the torque" in warning


def test_a_disturbance_that_takes_the_whole_authority_is_refused(tmp_path: Path):
    path = tmp_path / "weak.toml"
    path.write_text(
        'extends = "paper"\nname = "weak"\n'
        "[disturbance]\namplitude_mNm = [0.7, 3.0, 0.7]\nperiod_min = 98.5\n"
        "phase_deg = [0.0, 0.0, 0.0]\n"
    )
    with pytest.raises(SynthesisError, match=r"disturbance\.amplitude_mNm.*about y"):
        body_weights(load_problem(path), "derived")
    with pytest.raises(SynthesisError, match="weights: one of"):
        body_weights(load_problem(), "mine")  # type: ignore[arg-type]
