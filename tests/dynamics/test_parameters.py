"""Named model parameters: layout, round trips, errors that name the entry."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from casadi_debris import load_problem
from casadi_debris.dynamics import ParameterLayout, Parameters
from casadi_debris.errors import InputShapeError, ModelError, ProblemFileError

PAPER = ParameterLayout()


def test_layout_names_follow_the_debris():
    assert PAPER.names == (
        "inertia_scale_x",
        "inertia_scale_y",
        "inertia_scale_z",
        "mass_kg",
        "array_angle_offset_rad",
        "bending_frequency_scale",
    )
    rigid = ParameterLayout(array_angles=0, has_bending_scale=False)
    assert rigid.names == ("inertia_scale_x", "inertia_scale_y", "inertia_scale_z", "mass_kg")
    assert rigid.size == 4


def test_layout_reads_entries_of_a_vector_by_name():
    p = np.array([1.1, 1.2, 1.3, 668.0, 0.5, 0.9])
    np.testing.assert_array_equal(PAPER.inertia_scale(p), [1.1, 1.2, 1.3])
    assert PAPER.mass_kg(p) == 668.0
    assert PAPER.array_angle_offset_rad(p) == 0.5
    assert PAPER.bending_frequency_scale(p) == 0.9


def test_round_trip_vector_and_mapping():
    p = np.array([1.17, 0.83, 1.0, 534.4, -math.pi, 1.2])
    named = Parameters.from_vector(PAPER, p)
    assert named.mass_kg == 534.4 and named.array_angle_offset_rad == -math.pi
    np.testing.assert_array_equal(named.to_vector(), p)
    assert Parameters.from_mapping(PAPER, named.to_dict()) == named


def test_replace_changes_only_the_named_entry():
    base = Parameters.from_vector(PAPER, [1, 1, 1, 668.0, 0.0, 1.0])
    changed = base.replace(inertia_scale_y=1.17)
    assert changed.inertia_scale == (1.0, 1.17, 1.0)
    assert changed.to_vector()[[0, 2, 3, 4, 5]].tolist() == [1, 1, 668.0, 0.0, 1.0]


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda b: b.replace(omega_bending1_rad_s=5.6), "unknown parameter 'omega_bending1_rad_s'"),
        (lambda b: b.replace(mass_kg=math.nan), "mass_kg must be finite"),
        (lambda b: b.replace(mass_kg=-1.0), "must be positive"),
        (lambda b: Parameters.from_vector(PAPER, [1, 1, 1]), "expected 6 numbers"),
        (
            lambda b: Parameters.from_mapping(
                ParameterLayout(array_angles=0, has_bending_scale=False), b.to_dict()
            ),
            "unknown ['array_angle_offset_rad', 'bending_frequency_scale']",
        ),
    ],
)
def test_bad_values_name_the_entry(call, message):
    base = Parameters.from_vector(PAPER, [1, 1, 1, 668.0, 0.0, 1.0])
    with pytest.raises((ModelError, InputShapeError), match=None) as raised:
        call(base)
    assert message in str(raised.value)


def test_model_nominal_matches_the_problem(problem):
    from casadi_debris.dynamics import build_model
    from casadi_debris.geometry import build_geometry

    model = build_model(problem, modes="first")
    nominal = model.nominal
    assert nominal.mass_kg == pytest.approx(build_geometry(problem).mass_kg)
    # The offset from each array's own nominal angle (the problem's arrays say theirs).
    assert nominal.array_angle_offset_rad == 0.0
    assert model.parameter_layout == ParameterLayout.for_problem(problem)
    # Every model of a problem shares one layout, whichever modes it keeps.
    assert build_model(problem, modes="all").parameter_names == model.parameter_names


def _independent(paper_data, angles: int = 2):
    from casadi_debris.config import problem_from_dict

    data = copy.deepcopy(paper_data)
    data["uncertainty"]["independent_array_angles"] = True
    data["montecarlo"] = {"corner_array_angles": angles, "samples": 10, "seed": 1}
    return problem_from_dict(data)


def test_independent_array_angles_are_one_parameter_per_array(paper_data):
    from casadi_debris.campaigns import corner_cases
    from casadi_debris.dynamics import build_model

    problem = _independent(paper_data)
    model = build_model(problem, modes="first")
    names = model.parameter_names
    assert names[4:6] == ("array1_angle_offset_rad", "array2_angle_offset_rad")
    # The same turn of both arrays is the shared offset of the paper's model.
    shared = build_model(load_problem(), modes="first")
    both = model.parameters(array1_angle_offset_rad=0.6, array2_angle_offset_rad=0.6)
    np.testing.assert_array_equal(
        np.array(model.mass_matrix(both)),
        np.array(shared.mass_matrix(shared.parameters(array_angle_offset_rad=0.6))),
    )
    apart = model.parameters(array1_angle_offset_rad=0.6, array2_angle_offset_rad=-0.6)
    assert not np.allclose(np.array(model.mass_matrix(apart)), np.array(model.mass_matrix(both)))
    # Corners: 2 angles per array, 2^2 x 2^5, every angle pair with every extreme.
    corners = corner_cases(model)
    assert len(corners) == 4 * 32
    pairs = {tuple(case.normalized[4:6]) for case in corners}
    assert pairs == {(a, b) for a in (-1.0, 0.0) for b in (-1.0, 0.0)}


def test_too_many_independent_corners_are_refused(paper_data):
    with pytest.raises(ProblemFileError, match=r"montecarlo\.corner_array_angles: .* 16\^2"):
        _independent(paper_data, angles=16)
