"""Balanced truncation keeps what matters and the unstable part."""

from __future__ import annotations

import control
import numpy as np

from casadi_debris.robust.synthesis import reduce_controller


def test_truncation_error_within_hankel_bound():
    rng = np.random.default_rng(5)
    full = control.rss(12, 3, 3, strictly_proper=False)
    while np.max(np.linalg.eigvals(full.A).real) >= -1e-3:
        full = control.rss(12, 3, 3, strictly_proper=False)
    del rng
    reduced = reduce_controller(full, 6)
    assert reduced.nstates == 6
    # ||G - G_r||_inf <= 2 * (sum of the discarded Hankel singular values)
    hankel = np.sort(control.hsvd(full))[::-1]
    error = control.linfnorm(full - reduced)[0]
    assert error <= 2 * hankel[6:].sum() * (1 + 1e-6)


def test_unstable_poles_are_kept():
    unstable = control.ss(control.tf([1.0, 2.0], [1.0, -0.5]))
    stable = control.ss(control.tf([1.0], [1.0, 3.0, 2.0])) * control.ss(
        control.tf([1.0], [1.0, 10.0])
    )
    system = control.append(unstable, stable, control.ss(control.tf([1.0], [1.0, 4.0])))
    reduced = reduce_controller(system, 3)
    assert reduced.nstates == 3
    assert np.sum(np.linalg.eigvals(reduced.A).real > 0) == 1
    assert np.any(np.isclose(np.linalg.eigvals(reduced.A), 0.5))


def test_small_controller_only_made_minimal():
    system = control.ss(control.tf([1.0], [1.0, 1.0]))
    assert reduce_controller(system, 25).nstates == 1
    # Unstable poles are never truncated, even below the requested order.
    kept = reduce_controller(control.ss(control.tf([1.0], [1.0, -1.0, -2.0])), 0)
    np.testing.assert_allclose(np.linalg.eigvals(kept.A), [2.0])


def test_a_slicot_warning_is_logged_not_shown(monkeypatch, caplog):
    """SLICOT's note that the minimal order is below the one asked goes to the log."""
    import logging
    import warnings

    import control as ct

    from casadi_debris.robust.synthesis import _reduce as reduce_module

    def balred(system, order, method):
        warnings.warn(
            "The selected order 25 is greater\nthan the minimal", UserWarning, stacklevel=2
        )
        return system

    monkeypatch.setattr(reduce_module.control, "balred", balred)
    system = ct.rss(6, 1, 1, strictly_proper=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any warning escaping would fail here
        with caplog.at_level(logging.INFO, logger="casadi_debris.robust.synthesis"):
            reduce_module.reduce_controller(system, 2)
    assert "The selected order 25 is greater than the minimal" in caplog.text
