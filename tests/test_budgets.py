"""Budgets against the paper (the tolerances of casadi_debris/data/paper_reference.toml)
and against textbook limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from casadi_debris.budgets import (
    budgets_as_dict,
    compute_budgets,
    detumble_time_s,
    edelbaum_dv,
    rocket_dv,
)
from casadi_debris.report import paper_figure


@pytest.fixture(scope="module")
def budgets(problem, geometry):
    return budgets_as_dict(compute_budgets(problem, geometry))


@pytest.mark.parametrize(
    "key",
    [
        "dv_one_stage_one_face_m_s",
        "dv_three_stages_one_face_m_s",
        "dv_one_stage_all_faces_m_s",
        "dv_all_stages_all_faces_m_s",
        "dv_cubesat_one_stage_m_s",
        "dv_transfer_m_s",
        "detumble_time_h",
    ],
)
def test_against_paper(budgets, key):
    figure = paper_figure(key)
    assert figure.accepts(budgets[key]), (budgets[key], figure.paper, figure.accepted)


def test_detumble_dv_is_about_paper(budgets):
    # Paper: "approximately 0.22 m/s", not judged in the report. The Δv is
    # proportional to the detumble time, so it is held to the time's tolerance.
    time_tolerance = paper_figure("detumble_time_h").tolerance
    assert time_tolerance is not None
    paper = paper_figure("detumble_dv_m_s").value
    assert time_tolerance.accepts(budgets["detumble_dv_m_s"], paper), budgets["detumble_dv_m_s"]


def test_stage_propellant_by_hand(budgets):
    # 0.64 mN x 500 h / (1000 s x 9.80665 m/s^2)
    assert budgets["stage_propellant_kg"] == pytest.approx(
        0.64e-3 * 500 * 3600 / 9806.65, rel=1e-12
    )
    assert budgets["stage_life_h"] == paper_figure("stage_life_h").value


def test_rocket_equation_small_burn_limit():
    # dv -> Isp g0 mp / m0 for mp << m0
    assert rocket_dv(1000.0, 9.80665, 668.0, 1e-6) == pytest.approx(
        9806.65 * 1e-6 / 668.0, rel=1e-8
    )


def test_edelbaum_limits():
    mu, r0, r1 = 398600.4418, 6928.137, 7063.137
    coplanar = edelbaum_dv(mu, r0, r1, 0.0)
    assert coplanar == pytest.approx(1e3 * abs(math.sqrt(mu / r0) - math.sqrt(mu / r1)), rel=1e-12)
    # Pure plane change at one radius: V sqrt(2 - 2 cos(pi di / 2)) = 2 V sin(pi di / 4)
    v = math.sqrt(mu / r0)
    di = math.radians(10.0)
    assert edelbaum_dv(mu, r0, r0, di) == pytest.approx(
        1e3 * 2 * v * math.sin(math.pi * di / 4), rel=1e-12
    )


def test_detumble_slowest_axis_decides():
    inertia = np.diag([100.0, 50.0, 200.0])
    authority = {"+x": 1e-3, "-x": 2e-3, "+y": 1e-3, "-y": 1e-3, "+z": 4e-3, "-z": 4e-3}
    # omega_x > 0 is braked by -x (2e-3): 100 / 2e-3 = 5e4 s; z: 200 / 4e-3 = 5e4 s; y: 5e4 s
    assert detumble_time_s(inertia, np.array([1.0, -1.0, 1.0]), authority) == pytest.approx(5e4)
    assert detumble_time_s(inertia, np.array([-1.0, 0.0, 0.0]), authority) == pytest.approx(1e5)
    assert detumble_time_s(inertia, np.zeros(3), authority) == 0.0


def test_full_rigid_detumble_longer(budgets):
    assert budgets["detumble_time_full_rigid_h"] > budgets["detumble_time_h"]
