"""Loop-at-a-time margins against textbook values."""

from __future__ import annotations

import math

import control
import numpy as np
import pytest

from casadi_debris.errors import SynthesisError
from casadi_debris.robust.margins import disk_margins, loop_at_a_time, loop_margins, return_ratio


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
