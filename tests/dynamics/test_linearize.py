"""Linearisation from the one CasADi model, checked against independent computations."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from casadi_debris.dynamics import (
    assembled_modes,
    build_model,
    flexible_frequencies,
    linearization_function,
    linearize,
)


def _free_free_frequencies(model, p):
    """Independent: det(K - w^2 (I - C diag(m, J)^-1 C^T)) = 0 from the mass matrix."""
    mass_matrix = np.array(model.mass_matrix(p))
    rigid, coupling = mass_matrix[:6, :6], mass_matrix[6:, :6]
    effective = np.eye(len(coupling)) - coupling @ np.linalg.solve(rigid, coupling.T)
    scale = model.parameter_layout.bending_frequency_scale(p)
    omegas = []
    for array in model.problem.arrays:
        for mode in array.modes:
            first_bending = (mode.kind, mode.order) == ("bending", 1)
            omegas.append(mode.omega_rad_s * (scale if first_bending else 1.0))
    stiffness = np.diag(np.array(omegas) ** 2)
    return np.sort(np.sqrt(scipy.linalg.eigh(stiffness, effective, eigvals_only=True)))


def test_rigid_part_is_inverse_inertia_double_integrator(problem):
    rigid = build_model(problem, modes=[])
    plant = linearize(rigid)
    inertia = np.array(rigid.rigid_inertia(rigid.nominal_parameters))
    np.testing.assert_allclose(plant.A[:3, 3:6], np.eye(3))
    np.testing.assert_allclose(plant.A[3:6], 0.0, atol=1e-15)
    np.testing.assert_allclose(plant.B[3:6], np.linalg.inv(inertia), rtol=1e-12)
    np.testing.assert_allclose(inertia, rigid.geometry.inertia_total_kgm2, rtol=1e-12)


def test_flexible_plant_is_rigid_at_low_frequency(model):
    plant = linearize(model)
    omega = 1e-4
    response = plant(1j * omega)  # (3, 3) complex
    np.testing.assert_allclose(
        -(omega**2) * response, np.linalg.inv(model.geometry.inertia_total_kgm2), rtol=1e-5
    )


def test_paper_ten_state_plant(problem):
    truncated = build_model(problem, modes="first")
    plant = linearize(truncated)
    assert plant.nstates == 10
    assert plant.input_labels == ["tau_x", "tau_y", "tau_z"]
    assert plant.output_labels == ["phi", "theta", "psi"]
    assert plant.state_labels[:6] == [
        "theta_x",
        "theta_y",
        "theta_z",
        "omega_x",
        "omega_y",
        "omega_z",
    ]


def test_truncation_moves_first_flexible_pole_less_than_two_percent(model, problem):
    full = flexible_frequencies(linearize(model))
    truncated = flexible_frequencies(linearize(build_model(problem, modes="first")))
    assert abs(truncated[0] / full[0] - 1) < 0.02
    assert abs(truncated[1] / full[1] - 1) < 0.02


@pytest.mark.parametrize("angle_deg", [0.0, 45.0, 90.0, 160.0])
def test_free_free_frequencies_match_generalised_eigenproblem(model, angle_deg):
    p = model.parameters(array_angle_offset_rad=math.radians(angle_deg))
    from_plant = flexible_frequencies(linearize(model, p))
    independent = _free_free_frequencies(model, p)
    # |lambda| of a lightly damped pole equals the undamped frequency to O(zeta^2)
    np.testing.assert_allclose(from_plant, independent, rtol=2e-4)


def test_free_free_above_cantilever_and_moving_with_array_angle(model):
    cantilever = {"bending1": 5.6, "torsion1": 19.3, "bending2": 35.4}
    modes = assembled_modes(model)
    for mode in modes:
        assert mode["omega_rad_s"] >= cantilever[mode["dominant_mode"]] * (1 - 1e-9)
    anti_phase = {}
    for angle in (0.0, 90.0):
        p = model.parameters(array_angle_offset_rad=math.radians(angle))
        bending = [m for m in assembled_modes(model, p) if m["dominant_mode"] == "bending1"]
        anti_phase[angle] = next(m["omega_rad_s"] for m in bending if m["in_phase"] is False)
    # At 0 deg the arrays bend along x and the anti-phase mode rocks the body about y
    # (J_yy = 451 kg m^2); at 90 deg about x (J_xx = 677): less coupling, lower frequency.
    assert anti_phase[0.0] > anti_phase[90.0] > 5.6


def test_bending_frequency_parameter_moves_the_mode(model):
    low = flexible_frequencies(linearize(model, model.parameters(bending_frequency_scale=0.8)))
    high = flexible_frequencies(linearize(model, model.parameters(bending_frequency_scale=1.2)))
    assert low[0] == pytest.approx(0.8 * flexible_frequencies(linearize(model))[0], rel=0.01)
    assert high[0] > low[0]


def test_star_tracker_is_first_order_low_pass(model, problem):
    bandwidth = problem.sensor.star_tracker_bandwidth_rad_s
    bare = linearize(model)
    sensed = linearize(model, sensor=True)
    assert sensed.nstates == bare.nstates + 3
    for omega in (0.01, 1.0, 50.0):
        ratio = sensed(1j * omega) @ np.linalg.inv(bare(1j * omega))
        np.testing.assert_allclose(
            ratio, bandwidth / (1j * omega + bandwidth) * np.eye(3), atol=1e-9
        )


def test_design_units_scale_the_plant(model):
    si = linearize(model, disturbance_input=True)
    design = linearize(model, disturbance_input=True, units="deg_mNm")
    assert design.input_labels[3:] == ["tau_d_x", "tau_d_y", "tau_d_z"]
    np.testing.assert_allclose(design(0.1j), si(0.1j) * (180 / math.pi) * 1e-3, rtol=1e-12)


def test_reused_function_gives_the_same_plant(model):
    fn = linearization_function(model)
    p = model.parameters(array_angle_offset_rad=1.0, inertia_scale_z=0.83)
    np.testing.assert_allclose(linearize(model, p, function=fn).A, linearize(model, p).A)
