"""Margins of the shipped controller (the paper's claims) and an independent check of the
margin computation."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from casadi_debris.config import default_controller_path
from casadi_debris.dynamics import build_model, linearize
from casadi_debris.report import paper_figure
from casadi_debris.robust.margins import (
    MARGIN_GRID,
    LoopAtATime,
    loop_at_a_time,
    margin_study,
    return_ratio,
)
from casadi_debris.robust.plant import Controller, sample_uncertainty

# The paper's margins with their accepted bounds (dB, deg, s), nominal and over sampled plants.
NOMINAL = paper_figure("margins_nominal")
SAMPLED = paper_figure("margins_sampled")
CI_SAMPLES = 300  # the paper samples 3000; `casadi-debris margins` does by default


@pytest.fixture(scope="module")
def controller():
    data = json.loads(default_controller_path().read_text())
    return Controller.from_dict(data).reduced


@pytest.fixture(scope="module")
def study(problem, controller):
    return margin_study(problem, controller, samples=CI_SAMPLES, workers=2)


def test_nominal_margins_meet_requirements(study):
    for m in study.nominal:
        assert NOMINAL.accepts([m.gain_margin_db, m.phase_margin_deg]), m
        # The nominal plant is one of the sampled ones: it meets their delay bound too.
        assert SAMPLED.component("delay_margin_s").accepts(m.delay_margin_s), m


def test_sampled_margins_meet_requirements(study):
    assert not study.unstable.any()
    worst = study.sampled_min()
    assert SAMPLED.accepts([worst[c.name] for c in SAMPLED.components]), worst
    assert study.samples.n_corners == 64 and len(study.sampled) == CI_SAMPLES


def test_margins_against_a_brute_force_grid(problem, controller):
    """python-control's own frequency response of the state-space return ratio on 200k points."""
    plant = linearize(build_model(problem), sensor=True, units="deg_mNm")
    ours = loop_at_a_time(plant, controller)
    omega = np.logspace(-4, 2, 200_000)
    for channel, margins in enumerate(ours):
        response = return_ratio(plant, controller, channel).frequency_response(omega)
        value = response.magnitude.ravel() * np.exp(1j * response.phase.ravel())
        crossover = np.argmin(np.abs(np.abs(value) - 1.0) + 10 * (np.abs(value) > 1.5))
        phase_margin = 180.0 + np.degrees(np.angle(value[crossover]))
        assert margins.phase_margin_deg == pytest.approx(phase_margin, abs=0.05)
        on_axis = np.flatnonzero(np.sign(value.imag[:-1]) != np.sign(value.imag[1:]))
        gains = [abs(value[k].real) for k in on_axis if value[k].real < 0]
        gm = min(abs(20 * np.log10(g)) for g in gains)
        assert margins.gain_margin_db == pytest.approx(gm, abs=0.02)


def test_parallel_and_serial_agree(problem, controller):
    serial = margin_study(problem, controller, samples=70, workers=1)
    parallel = margin_study(problem, controller, samples=70, workers=2)
    np.testing.assert_array_equal(serial.sampled, parallel.sampled)


def _reference_margins(loop, omega):
    """Margins of a SISO state-space return ratio the slow, direct way.

    One LU solve per frequency on the grid; every crossing (not only those
    near the smallest margin) refined by scipy's brentq on single LU solves.
    Returns (upper gain dB, lower gain dB, phase deg, delay s, crossover rad/s).
    """
    a, b, c = loop.A, loop.B, loop.C

    def at(w):
        return complex((c @ np.linalg.solve(1j * w * np.eye(len(a)) - a, b))[0, 0])

    def root(function, k):
        x = brentq(lambda x: function(at(math.exp(x))), *np.log(omega[k : k + 2]), xtol=1e-13)
        return math.exp(x)

    values = np.array([at(w) for w in omega])
    gains = []
    for k in np.flatnonzero(np.sign(values.imag[:-1]) != np.sign(values.imag[1:])):
        point = at(root(lambda v: v.imag, k))
        if point.real < 0:
            gains.append(-20 * math.log10(-point.real))  # > 0: upper, < 0: lower margin
    magnitude = np.abs(values) - 1.0
    phases = []
    for k in np.flatnonzero(np.sign(magnitude[:-1]) != np.sign(magnitude[1:])):
        w = root(lambda v: abs(v) - 1.0, k)
        phase = 180.0 + math.degrees(np.angle(at(w)))
        phases.append((phase - 360.0 if phase > 180.0 else phase, w))
    phase, crossover = min(phases)
    return (
        min((g for g in gains if g > 0), default=math.inf),
        min((-g for g in gains if g < 0), default=math.inf),
        phase,
        min(math.radians(p) / w for p, w in phases),
        crossover,
    )


def test_fast_margins_against_a_direct_computation_on_sampled_plants(problem, controller):
    """The sweep's path (block-diagonal Schur responses, return ratios from 3 x 3 responses,
    batched Chandrupatla refinement) against the return ratio's own state space, LU solves and
    brentq, on corners, the three worst plants of the shipped 3000-sample sweep (gain: 33,
    phase: 36, delay: 2344) and others. Agreement to 1e-6 (dB, deg, s) is far inside the 1e-3
    that the reported figures need; observed ~1e-11."""
    model = build_model(problem)
    parameters = sample_uncertainty(model, 3000).parameters
    loops = LoopAtATime(controller)
    for index in (0, 33, 36, 63, 64, 500, 2344):
        plant = linearize(model, parameters[index], sensor=True, units="deg_mNm")
        for channel, fast in enumerate(loops(plant)):
            reference = _reference_margins(return_ratio(plant, controller, channel), MARGIN_GRID)
            ours = (
                fast.upper_gain_margin_db,
                fast.lower_gain_margin_db,
                fast.phase_margin_deg,
                fast.delay_margin_s,
                fast.crossover_rad_s,
            )
            np.testing.assert_allclose(ours, reference, rtol=0, atol=1e-6)
