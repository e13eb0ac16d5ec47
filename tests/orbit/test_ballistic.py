"""Drag areas of the debris' faces: Cauchy's mean area, held attitudes by hand."""

from __future__ import annotations

import numpy as np
import pytest

from casadi_debris.errors import InputShapeError
from casadi_debris.orbit import ballistic, drag_area_m2


def test_tumbling_area_is_a_quarter_of_all_faces(problem, geometry) -> None:
    hub = problem.hub.size_m
    box = 2.0 * (hub[0] * hub[1] + hub[1] * hub[2] + hub[0] * hub[2])
    arrays = sum(2.0 * a.length_m * a.width_m for a in problem.arrays)
    assert drag_area_m2(problem, geometry) == pytest.approx((box + arrays) / 4.0)


def test_tumbling_area_is_the_mean_over_random_flow_directions(problem, geometry) -> None:
    rng = np.random.default_rng(3)
    flows = rng.normal(size=(1500, 3))
    areas = [drag_area_m2(problem, geometry, flow) for flow in flows]
    assert np.mean(areas) == pytest.approx(drag_area_m2(problem, geometry), rel=0.03)


def test_held_areas_by_hand(problem, geometry) -> None:
    # Flow along +x: the hub's x face (3 m x 1 m) and both arrays face on (2 x 2.5 m x 2 m).
    assert drag_area_m2(problem, geometry, np.array([1.0, 0.0, 0.0])) == pytest.approx(13.0)
    # Along y: the hub's 0.75 m x 1 m end; the arrays are edge on.
    assert drag_area_m2(problem, geometry, np.array([0.0, -1.0, 0.0])) == pytest.approx(0.75)


def test_ballistic_coefficient_of_the_paper_debris(problem) -> None:
    b = ballistic(problem)
    assert b.mass_kg == pytest.approx(668.0)
    assert b.drag_coefficient == problem.environment.drag_coefficient == 2.2
    assert b.coefficient_kg_m2 == pytest.approx(668.0 / (2.2 * 8.0))


@pytest.mark.parametrize("cd", [0.0, -1.0, float("nan")])
def test_bad_drag_coefficient_names_the_field(problem, cd: float) -> None:
    with pytest.raises(InputShapeError, match="drag coefficient"):
        ballistic(problem, drag_coefficient=cd)


def test_bad_flow_direction_names_the_field(problem, geometry) -> None:
    with pytest.raises(InputShapeError, match="flow direction"):
        drag_area_m2(problem, geometry, np.zeros(3))
