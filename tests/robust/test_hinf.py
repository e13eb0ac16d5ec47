"""H-infinity synthesis by bisection against SLICOT's own gamma iteration (``control.hinfsyn``)."""

from __future__ import annotations

import control
import numpy as np
import pytest

from casadi_debris.errors import SynthesisError
from casadi_debris.robust.examples import distillation_column
from casadi_debris.robust.synthesis import hinf_synthesis, well_conditioned


def _mixed_sensitivity(plant):
    """SISO mixed sensitivity: z1 = W1 S w, z2 = W2 K S w (augw)."""
    w1 = control.tf([0.5, 0.5 * 0.1 * 2], [1.0, 0.1 * 0.02])
    w2 = control.tf([1.0, 0.5], [0.01, 5.0])
    return control.augw(plant, w1, w2)


@pytest.mark.parametrize(
    "plant",
    [
        control.tf([1.0], [1.0, 1.1, 0.1]),
        control.tf([2.0, 1.0], [1.0, 0.5, 4.0]),
        control.tf([10.0], [1.0, 3.0, 2.0, 0.1]),
    ],
)
def test_gamma_matches_hinfsyn(plant):
    p = control.ss(_mixed_sensitivity(control.ss(plant)))
    ours = hinf_synthesis(p, 1, 1, tolerance=1e-3)
    _, _closed, gamma, _ = control.hinfsyn(p, 1, 1)
    assert ours.gamma == pytest.approx(gamma, rel=0.01)
    # the controller we return achieves the norm we report
    assert control.linfnorm(p.lft(ours.controller, 1, 1))[0] == pytest.approx(ours.gamma, rel=1e-6)
    assert np.all(np.linalg.eigvals(p.lft(ours.controller, 1, 1).A).real < 0)


def test_well_conditioned_keeps_the_transfer_function():
    system = control.ss(control.tf([1.0, 1e-4], [1.0, 1e3, 1e-2]))
    big = control.ss(system.A * 1.0, system.B * 1e6, system.C * 1e-6, system.D)
    conditioned = well_conditioned(big)
    omega = np.logspace(-6, 5, 30)
    np.testing.assert_allclose(
        conditioned.frequency_response(omega).magnitude,
        big.frequency_response(omega).magnitude,
        rtol=1e-8,
    )


def _random_plant(seed: int) -> tuple[control.StateSpace, int, int]:
    """A seeded generalised plant: 3-7 states, 2 disturbances and errors, 1-2 controls
    and measurements, D22 = 0, mostly stable, sometimes not."""
    rng = np.random.default_rng(seed)
    n, n_controls, n_measurements = 3 + seed % 5, 1 + seed % 2, 1 + (seed // 2) % 2
    a = rng.normal(size=(n, n))
    if rng.uniform() < 0.7:
        a -= (np.max(np.linalg.eigvals(a).real) + rng.uniform(0.1, 1.0)) * np.eye(n)
    b = rng.normal(size=(n, 2 + n_controls))
    c = rng.normal(size=(2 + n_measurements, n))
    d = 0.5 * rng.normal(size=(2 + n_measurements, 2 + n_controls))
    d[2:, 2:] = 0.0
    return control.ss(a, b, c, d), n_measurements, n_controls


def _rescaled(plant: control.StateSpace, seed: int) -> control.StateSpace:
    """The same transfer function with states scaled by 1e-4 .. 1e4."""
    t = 10.0 ** np.random.default_rng(seed + 1000).uniform(-4, 4, plant.nstates)
    return control.ss(
        plant.A * (1 / t)[:, None] * t[None, :], plant.B / t[:, None], plant.C * t[None, :], plant.D
    )


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(24))
def test_gamma_reaches_hinfsyn_on_random_plants_however_scaled(seed):
    plant, n_measurements, n_controls = _random_plant(seed)
    try:
        controller, _, reported, _ = control.hinfsyn(plant, n_measurements, n_controls)
    except Exception:  # slycot raises several types; the case is then skipped
        pytest.skip("hinfsyn finds no controller")
    achieved = control.linfnorm(plant.lft(controller, n_controls, n_measurements))[0]
    for realisation in (plant, _rescaled(plant, seed)):
        ours = hinf_synthesis(realisation, n_measurements, n_controls)
        # Never worse than hinfsyn's controller; within 1 % of its gamma where that
        # gamma is what its controller achieves (it sometimes reports less).
        assert ours.gamma <= 1.01 * achieved
        if reported == pytest.approx(achieved, rel=0.01):
            assert ours.gamma == pytest.approx(reported, rel=0.01)
        closed = plant.lft(ours.controller, n_controls, n_measurements)
        assert np.max(np.linalg.eigvals(closed.A).real) < 0
        assert control.linfnorm(closed)[0] == pytest.approx(ours.gamma, rel=1e-4)


def test_distillation_first_step_on_any_realisation():
    # The textbook plant with the weight's near-integrator (pole -1e-6 rad/s):
    # python-control's hinfsyn reaches 1.1798; a minimal-and-balanced realisation
    # alone makes fixed-gamma solves return loops 40 times worse than gamma.
    plant = distillation_column()
    for realisation in (plant, well_conditioned(plant), _rescaled(plant, 7)):
        assert hinf_synthesis(realisation, 2, 2).gamma == pytest.approx(1.1798, rel=0.01)


def test_no_controller_is_an_error_naming_the_checks():
    # u reaches no output: D12 = 0 and no path through the states.
    plant = control.ss([[-1.0]], [[1.0, 0.0]], [[1.0], [1.0]], [[0.0, 0.0], [1.0, 0.0]])
    with pytest.raises(SynthesisError, match="stabilisability"):
        hinf_synthesis(plant, 1, 1)
