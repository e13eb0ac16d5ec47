"""Loop-at-a-time margins against textbook values; the fast frequency response, return
ratios and root finder against direct computations."""

from __future__ import annotations

import math

import control
import numpy as np
import pytest

from casadi_debris.errors import SynthesisError
from casadi_debris.robust.margins import (
    disk_margins,
    loop_at_a_time,
    loop_margins,
    return_ratio,
    return_ratios,
    sampled_loop_at_a_time,
)
from casadi_debris.robust.margins._loop import _bracketed_roots
from casadi_debris.robust.plant import FrequencyResponse


def _diagonal(transfer, n=3):
    return control.append(*[control.ss(transfer)] * n)


@pytest.mark.parametrize("k", [1.0, 2.0, 4.0])
def test_third_order_loop(k):
    # L = k / (s (s + 1) (s + 2)): phase crosses -180 deg at sqrt(2) rad/s, |L| = k / 6 there.
    plant = _diagonal(control.tf([k], [1.0, 3.0, 2.0, 0.0]))
    margins = loop_at_a_time(plant, _diagonal(control.tf([1.0], [1.0])))
    for m in margins:
        assert m.upper_gain_margin_db == pytest.approx(20 * math.log10(6 / k), rel=1e-9)
        # phase margin at |L| = 1: solve k = w sqrt(w^2 + 1) sqrt(w^2 + 4)
        w = np.roots([1.0, 0.0, 5.0, 0.0, 4.0, 0.0, -(k**2)])
        wc = float(np.real(w[(np.abs(w.imag) < 1e-9) & (w.real > 0)][0]))
        phase = -90 - math.degrees(math.atan(wc) + math.atan(wc / 2))
        assert m.phase_margin_deg == pytest.approx(180 + phase, abs=1e-6)
        assert m.delay_margin_s == pytest.approx(math.radians(180 + phase) / wc, rel=1e-6)


def test_conditionally_stable_loop_reports_lower_margin():
    # L = 2 (s + 1)^2 / s^3: closed loop s^3 + 2 s^2 + 4 s + 2 is stable; the phase
    # -270 + 2 atan(w) crosses -180 deg at w = 1, where |L| = 4: lower margin 20 log10(4).
    plant = _diagonal(control.tf([1.0, 2.0, 1.0], [1.0, 0.0, 0.0, 0.0]))
    for m in loop_at_a_time(plant, _diagonal(control.tf([2.0], [1.0]))):
        assert m.lower_gain_margin_db == pytest.approx(20 * math.log10(4.0), rel=1e-9)
        assert math.isinf(m.upper_gain_margin_db)
        assert m.gain_margin_db == m.lower_gain_margin_db


def test_cross_coupled_loop_breaks_one_channel():
    # Two channels coupled only through the controller: breaking loop 0 must see loop 1 closed.
    plant = control.append(
        control.ss(control.tf([1.0], [1.0, 1.0])), control.ss(control.tf([1.0], [1.0, 1.0]))
    )
    controller = control.ss([], [], [], [[2.0, 1.0], [1.0, 2.0]])
    loop = return_ratio(plant, controller, 0)
    # By hand at s = 0: u1 = -(2 y1 + y2), y = u / (s + 1); with y1 = v: L = 2 - 1 * 1/(1 + 2) = 5/3
    assert float(np.real(loop(0))) == pytest.approx(5 / 3, rel=1e-9)


def test_unstable_loop_rejected():
    plant = _diagonal(control.tf([1.0], [1.0, -1.0]))
    with pytest.raises(SynthesisError, match="unstable"):
        loop_at_a_time(plant, _diagonal(control.tf([0.1], [1.0])))


def test_disk_margin_of_first_order_loop():
    # L = k / s: S - T = (s - k) / (s + k) is all-pass, so the balanced disk margin
    # alpha = 1 / ||(S - T) / 2|| = 2, with disk phase margin 90 deg.
    plant = _diagonal(control.tf([1.0], [1.0, 0.0]))
    omega = np.logspace(-3, 3, 500)
    alpha, gain_db, phase = disk_margins(plant, _diagonal(control.tf([2.0], [1.0])), omega)
    assert alpha == pytest.approx(2.0, rel=1e-2)
    assert phase == pytest.approx(90.0, rel=1e-2)
    assert gain_db > 40  # infinite in theory: alpha = 2 puts the disk's gain bound at infinity


def test_loop_margins_of_pure_gain():
    margins = loop_margins(control.ss(control.tf([0.5], [1.0])))
    assert math.isinf(margins.gain_margin_db)


def _dense_response(system, omega):
    """C (jw I - A)^-1 B + D by one LU solve per frequency."""
    a, b, c, d = system.A, system.B, system.C, system.D
    return np.array([c @ np.linalg.solve(1j * w * np.eye(len(a)) - a, b) + d for w in omega])


def _flexible_plant(seed=0):
    """Three double integrators, a repeated sensor pole, lightly damped modes, coupled inputs."""
    rng = np.random.default_rng(seed)
    rigid = control.append(*[control.ss(control.tf([1.0], [1.0, 0.0, 0.0]))] * 3)
    modes = control.append(
        *[control.ss(control.tf([w**2], [1.0, 2 * 0.005 * w, w**2])) for w in (5.6, 5.7, 19.3)]
    )
    sensor = control.append(*[control.ss(control.tf([50.0], [1.0, 50.0]))] * 3)
    mixing = control.ss([], [], [], rng.normal(size=(3, 3)))
    return sensor * (rigid * mixing + modes * control.ss([], [], [], rng.normal(size=(3, 3))))


def _random_system(seed=1):
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(12, 12)) - 3.0 * np.eye(12)
    return control.ss(
        a, rng.normal(size=(12, 3)), rng.normal(size=(2, 12)), rng.normal(size=(2, 3))
    )


def test_frequency_response_against_dense_solves():
    omega = np.logspace(-3, 2, 400)
    for system in (
        _flexible_plant(),
        control.ss(control.tf([1.0, 2.0], [1.0, 3.0, 0.0, 0.0])),  # Jordan block at 0
        control.ss([], [], [], [[2.0, -1.0]]),  # static gain
        _random_system(),
    ):
        ours = FrequencyResponse(system)(omega)
        dense = _dense_response(system, omega)
        # 1e-9: digits lost next to a Jordan block at 0 (so do the dense solves, 1e-11 there)
        np.testing.assert_allclose(ours, dense, rtol=1e-9, atol=1e-12 * np.abs(dense).max())
        few = FrequencyResponse(system)(omega[::97])
        np.testing.assert_allclose(few, dense[::97], rtol=1e-9, atol=1e-12 * np.abs(dense).max())


def test_frequency_response_of_integrators_is_exact():
    # 1 / s^2 = -1 / w^2 and 1 / s^3 = j / w^3: defective eigenvalues at 0 (a Jordan chain)
    omega = np.logspace(-2, 2, 200)
    double = FrequencyResponse(control.ss(control.tf([1.0], [1.0, 0.0, 0.0])))(omega)
    triple = FrequencyResponse(control.ss(control.tf([1.0], [1.0, 0.0, 0.0, 0.0])))(omega)
    np.testing.assert_allclose(double[:, 0, 0], -1 / omega**2, rtol=1e-12)
    np.testing.assert_allclose(triple[:, 0, 0], 1j / omega**3, rtol=1e-9)


@pytest.mark.parametrize("channels", [1, 2, 3])
def test_return_ratios_match_the_state_space_return_ratio(channels):
    rng = np.random.default_rng(channels)
    plant = control.ss(
        -np.diag(rng.uniform(0.5, 2.0, 2 * channels)),
        rng.normal(size=(2 * channels, channels)),
        rng.normal(size=(channels, 2 * channels)),
        np.zeros((channels, channels)),
    )
    controller = control.ss([], [], [], rng.normal(size=(channels, channels)))
    omega = np.logspace(-2, 2, 50)
    ours = return_ratios(_dense_response(plant, omega), _dense_response(controller, omega))
    for i in range(channels):
        expected = _dense_response(return_ratio(plant, controller, i), omega)[:, 0, 0]
        np.testing.assert_allclose(ours[:, i], expected, rtol=1e-12, atol=1e-14)


def test_bracketed_roots_to_tolerance():
    # cos on [1, 2] and [4, 5], x^3 - 2 on [1, 2], and a root on a bracket end's neighbour
    low, high = np.array([1.0, 4.0, 1.0, -1.0]), np.array([2.0, 5.0, 2.0, 1e-300])
    offsets = np.array([0.0, 0.0, 2.0, 0.0])

    def function(x, which):
        kind = np.array([0, 0, 1, 2])[which]
        return np.select([kind == 0, kind == 1], [np.cos(x), x**3 - offsets[which]], x)

    every = np.arange(4)
    roots = _bracketed_roots(function, low, high, function(low, every), function(high, every))
    expected = [math.pi / 2, 3 * math.pi / 2, 2 ** (1 / 3), 0.0]
    np.testing.assert_allclose(roots, expected, rtol=0, atol=2e-12)


def test_sampled_data_margins_are_python_controls_on_a_decoupled_loop() -> None:
    """Three double integrators under PD: each loop broken alone is the SISO loop,
    whose discrete margins python-control gives on its own."""
    inertia, period_s = np.array([2.0, 3.0, 5.0]), 0.1
    plants, controllers = [], []
    for j in inertia:
        plants.append(control.ss([[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0 / j]], [[1.0, 0.0]], 0.0))
        controllers.append(control.ss(control.tf([1.6 * j, j], [0.05, 1.0])))
    found = sampled_loop_at_a_time(control.append(*plants), control.append(*controllers), period_s)
    for plant, controller, margins in zip(plants, controllers, found, strict=True):
        loop = control.sample_system(controller, period_s, "zoh") * control.sample_system(
            plant, period_s, "zoh"
        )
        gain, phase_deg, _, crossover = control.margin(loop)
        assert margins.phase_margin_deg == pytest.approx(phase_deg, rel=1e-9)
        assert margins.gain_margin_db == pytest.approx(20 * np.log10(gain), rel=1e-9)
        assert margins.crossover_rad_s == pytest.approx(crossover, rel=1e-9)
    # Sampling costs margin against the continuous loop.
    continuous = loop_at_a_time(control.append(*plants), control.append(*controllers))
    pairs = zip(found, continuous, strict=True)
    assert all(s.phase_margin_deg < c.phase_margin_deg for s, c in pairs)


def test_a_sampled_loop_unstable_at_its_rate_is_refused() -> None:
    plant = control.ss([[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0]], [[1.0, 0.0]], 0.0)
    stiff = control.ss(control.tf([400.0, 10000.0], [0.001, 1.0]))  # crossover far past Nyquist
    with pytest.raises(SynthesisError, match="unstable"):
        sampled_loop_at_a_time(plant, stiff, 0.1)
