"""H-infinity synthesis by bisection against SLICOT's own gamma iteration."""

from __future__ import annotations

import control
import numpy as np
import pytest

from casadi_debris.robust.hinf import hinf_synthesis, well_conditioned


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
