"""``layout.png`` draws the arrays, where the problem puts them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from matplotlib.patches import Polygon

from casadi_debris import load_problem
from casadi_debris.plots import VIEWS, array_outlines_corner_m, layout_figure, save_figure
from casadi_debris.studies.placement import PlacementSettings, optimise_placement


def _box(corners: np.ndarray) -> np.ndarray:
    """Least and greatest coordinate per axis, shape (2, 3)."""
    return np.array([corners.min(axis=0), corners.max(axis=0)])


def test_the_papers_arrays_are_the_panels_the_paper_gives() -> None:
    # Read from the paper: 2 m wide (along y), 2.5 m long, hinged at [0.4, 1.4, 0] and
    # [0.4, 1.4, 1] in the hub-corner frame, one below the hub and one above it.
    lower, upper = array_outlines_corner_m(load_problem())
    np.testing.assert_allclose(_box(lower), [[0.4, 0.4, -2.5], [0.4, 2.4, 0.0]], atol=1e-12)
    np.testing.assert_allclose(_box(upper), [[0.4, 0.4, 1.0], [0.4, 2.4, 3.5]], atol=1e-12)


def test_a_turned_array_is_a_turned_panel(tmp_path: Path) -> None:
    """Turned 90 deg about +z the paper's arrays lie across x: 2 m wide along -x / +x."""
    child = tmp_path / "turned.toml"
    child.write_text(
        'extends = "paper"\n'
        '[[arrays]]\nhinge_corner_m = [0.4, 1.4, 1.0]\ndirection = "+z"\nmass_kg = 42.0\n'
        "length_m = 2.5\nwidth_m = 2.0\ninertia_kgm2 = [17.0, 62.0, 80.0]\nangle_deg = 90.0\n"
        "damping_ratio = 0.005\n"
    )
    [panel] = array_outlines_corner_m(load_problem(child))
    np.testing.assert_allclose(_box(panel), [[-0.6, 1.4, 1.0], [1.4, 1.4, 3.5]], atol=1e-12)


@pytest.mark.parametrize("name", ["paper", "rigid_no_arrays"])
def test_the_layout_figure_draws_each_array_in_every_view(tmp_path, name) -> None:
    problem = load_problem(name)
    study = optimise_placement(problem, PlacementSettings(count=(8, 8)), grid=(2, 2))
    figure = layout_figure(study)
    drawn = [[[p for p in axis.patches if isinstance(p, Polygon)] for axis in figure.axes]]
    save_figure(figure, tmp_path / "layout.png")
    assert (tmp_path / "layout.png").stat().st_size > 0
    [per_view] = drawn
    outlines = array_outlines_corner_m(problem)
    for (first, second), polygons in zip(VIEWS, per_view, strict=True):
        assert len(polygons) == len(problem.arrays)
        for polygon, corners in zip(polygons, outlines, strict=True):
            shown = polygon.get_xy()[:4]
            np.testing.assert_allclose(shown, corners[:, [first, second]], atol=1e-12)
