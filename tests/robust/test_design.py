"""The design pipeline, and the shipped controller against the paper's robustness claims."""

from __future__ import annotations

import json

import numpy as np
import pytest

import casadi_debris
from casadi_debris.config import default_controller_path
from casadi_debris.dynamics import build_model, linearize
from casadi_debris.errors import SynthesisError
from casadi_debris.report import paper_figure
from casadi_debris.robust.margins import closed_loop_poles
from casadi_debris.robust.plant import (
    Controller,
    box_corners,
    generalized_plant,
    parameters_from_normalized,
    performance_weights,
    weight_system,
)
from casadi_debris.robust.synthesis import SynthesisSettings, closed_loop_mu, design_controller

# The paper's robust performance (peak mu, full and reduced) and reduced order,
# with their accepted bounds.
MU_PEAK = paper_figure("mu_peak")
REDUCED_ORDER = paper_figure("controller_order").component("reduced")


@pytest.fixture(scope="module")
def shipped() -> Controller:
    path = default_controller_path()
    return Controller.from_dict(json.loads(path.read_text()), str(path))


@pytest.fixture(scope="module")
def shipped_plant(problem, shipped):
    """The generalised plant rebuilt from the problem and the weight stored in the file."""
    model = build_model(problem, modes=shipped.details["design_plant_modes"])
    weight = weight_system(
        np.array(shipped.details["uncertainty_weight"]["coefficients_k_wz_zetaz_wp_zetap"])
    )
    return generalized_plant(
        linearize(model, sensor=True, units="deg_mNm"), weight, performance_weights(problem)
    )


def test_shipped_controller_belongs_to_the_shipped_problem(problem, shipped):
    assert shipped.problem_sha256 == problem.plant_sha256
    assert REDUCED_ORDER.accepts(shipped.reduced.nstates)
    assert shipped.full is not None and shipped.full.nstates > shipped.reduced.nstates


def test_shipped_controller_robust_performance(shipped_plant, shipped):
    # An independent, denser grid than the design's: mu <= 1 for both controllers.
    omega = np.logspace(-5, 3, 400)
    _, full = closed_loop_mu(shipped_plant, shipped.full, omega)
    _, reduced = closed_loop_mu(shipped_plant, shipped.reduced, omega)
    assert MU_PEAK.accepts([full.peak, reduced.peak]), (full.peak, reduced.peak)
    assert full.peak == pytest.approx(shipped.mu_peak, rel=0.01)
    assert reduced.peak == pytest.approx(shipped.mu_peak_reduced, rel=0.01)


@pytest.mark.parametrize("modes", ["first", "all"])
def test_shipped_controller_stabilises_every_corner(problem, shipped, modes):
    model = build_model(problem, modes=modes)
    for p in parameters_from_normalized(model, box_corners(6)):
        plant = linearize(model, p, sensor=True, units="deg_mNm")
        assert np.max(closed_loop_poles(plant, shipped.reduced).real) < 0


def test_quick_design_is_consistent(problem):
    settings = SynthesisSettings(samples=70, mu_points=40, d_orders=(1,), max_iterations=1)
    design = design_controller(problem, settings)
    summary = design.summary()
    assert summary.w_fit_samples == 70 and summary.w_fit_margin >= 1.0 - 1e-9
    assert summary.mu_peak <= design.musyn.iterations[0].mu_peak
    _, recomputed = closed_loop_mu(design.plant, design.record.reduced, design.musyn.omega)
    assert recomputed.peak == pytest.approx(summary.mu_peak_reduced, rel=1e-9)
    data = design.record.to_dict()
    assert data["mu_per_iteration"][0] == pytest.approx(design.musyn.hinf_gamma_first, rel=0.02)
    assert data["problem_sha256"] == problem.plant_sha256
    assert data["seed"] == problem.uncertainty.seed
    assert data["toolkit_version"] == casadi_debris.__version__


@pytest.mark.slow
def test_full_synthesis_reproduces_the_shipped_design(problem, shipped):
    """The paper's mu-synthesis, redone: robust performance reached, at least as well as
    the shipped design (a resynthesis may find a lower mu; it must not lose ground)."""
    design = design_controller(problem)
    summary = design.summary()
    assert MU_PEAK.accepts([summary.mu_peak, summary.mu_peak_reduced]), summary
    assert REDUCED_ORDER.accepts(summary.order_reduced), summary.order_reduced
    assert summary.mu_peak <= shipped.mu_peak * 1.02, (summary.mu_peak, shipped.mu_peak)


@pytest.mark.parametrize(
    ("knobs", "field"),
    [
        ({"d_orders": (1000,)}, "d_orders"),
        ({"d_orders": ()}, "d_orders"),
        ({"d_orders": (1, True)}, "d_orders"),
        ({"mu_points": 5}, "mu_points"),
        ({"mu_points": 150.0}, "mu_points"),
        ({"max_iterations": -1}, "max_iterations"),
        ({"samples": 0}, "samples"),
        ({"seed": 2**32}, "seed"),
        ({"reduced_order": 0}, "reduced_order"),
    ],
)
def test_settings_outside_their_range_are_refused_naming_the_knob(knobs, field) -> None:
    with pytest.raises(SynthesisError, match=f"^{field}: "):
        SynthesisSettings(**knobs)
