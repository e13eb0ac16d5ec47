"""The deorbit planner: least Δv by an independent check on either side, offline, bad input."""

from __future__ import annotations

import dataclasses
import math
import socket

import pytest
from scipy.optimize import brentq

from casadi_debris.errors import InputShapeError
from casadi_debris.orbit import (
    STRATEGIES,
    DeorbitModel,
    DeorbitPlan,
    DeorbitSettings,
    plan_deorbit,
    solar_case,
)
from casadi_debris.orbit import _atmosphere as atmosphere
from tests.orbit.test_lifetime_msis import INCLINATION_DEG, Atmosphere, Spiral, lifetime_years

HIGH_SPIRAL = DeorbitSettings(solar=("high",), strategies=("spiral",), minimum_swarm=False)


@pytest.fixture(scope="module")
def high_plan(problem):
    return plan_deorbit(problem, HIGH_SPIRAL)


def test_least_dv_is_least(problem, high_plan) -> None:
    case = high_plan.cases[0]
    assert case.meets_five_year_rule and case.within_capacity
    assert 0.0 < case.deorbit_dv_m_s < high_plan.capacity_dv_m_s
    model = DeorbitModel.from_problem(problem, HIGH_SPIRAL)
    density = model.density(solar_case("high"))
    horizon = HIGH_SPIRAL.horizon_years
    enough = model.fly(case.deorbit_dv_m_s, density, 180.0, horizon).reentry_years
    short = model.fly(case.deorbit_dv_m_s - 0.2, density, 180.0, horizon).reentry_years
    assert enough <= 5.0 < short
    assert case.natural_lifetime_years > 5.0


def test_a_given_model_is_used_as_is(problem, high_plan) -> None:
    """The plan of the model it would build is the plan it builds; a lighter body (some
    propellant spent) decays faster and needs less Δv, with that mass in the plan."""
    model = DeorbitModel.from_problem(problem, HIGH_SPIRAL)
    same = plan_deorbit(model, HIGH_SPIRAL)
    assert same.to_json() == high_plan.to_json()
    lighter = DeorbitModel.from_problem(problem, HIGH_SPIRAL, mass_kg=model.decay.mass_kg - 50.0)
    plan = plan_deorbit(lighter, HIGH_SPIRAL)
    assert plan.mass_kg == pytest.approx(model.decay.mass_kg - 50.0)
    assert plan.ballistic_coefficient_kg_m2 < high_plan.ballistic_coefficient_kg_m2
    assert plan.deorbit_dv_m_s < high_plan.deorbit_dv_m_s


def test_propellant_follows_the_rocket_equation(high_plan) -> None:
    case = high_plan.cases[0]
    ve = case.impulse_Ns / case.propellant_kg
    mass = high_plan.mass_kg
    assert ve * math.log(mass / (mass - case.propellant_kg)) == pytest.approx(case.flown_dv_m_s)
    # The strongest direction gives 4 x 0.64 mN at most.
    assert case.firing_time_h * 3600.0 >= case.impulse_Ns / 2.56e-3 * (1 - 1e-9)


def test_summary_keys_and_json_round_trip(high_plan) -> None:
    data = high_plan.to_json()
    for key in (
        "deorbit_dv_m_s",
        "reentry_years",
        "meets_five_year_rule",
        "natural_lifetime_years",
    ):
        assert key in data
    assert set(data["reentry_years"]) == {"high"}
    assert DeorbitPlan.from_json(data).to_json() == data


def test_planner_runs_with_the_network_blocked(problem, monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(*args: object, **kwargs: object) -> None:
        raise OSError("network access in a test")

    monkeypatch.setattr(socket, "socket", refuse)
    atmosphere.density_table.cache_clear()
    plan = plan_deorbit(problem, HIGH_SPIRAL)
    assert plan.meets_five_year_rule


def test_a_lower_limit_needs_more_dv(problem, high_plan) -> None:
    settings = dataclasses.replace(HIGH_SPIRAL, limit_years=3.0)
    assert plan_deorbit(problem, settings).deorbit_dv_m_s > high_plan.deorbit_dv_m_s


def test_perigee_arcs_beat_the_spiral_when_much_dv_is_needed(problem) -> None:
    # Under mean activity the paper's debris needs tens of m/s; lowering the perigee
    # at apogee needs less than lowering the whole orbit.
    model = DeorbitModel.from_problem(problem, DeorbitSettings())
    density = model.density(solar_case("mean"))
    dv = 60.0
    spiral = model.fly(dv, density, STRATEGIES["spiral"], 200.0).reentry_years
    perigee = model.fly(dv, density, STRATEGIES["perigee"], 200.0).reentry_years
    assert perigee < spiral


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"solar": ("extreme",)}, "solar activity"),
        ({"solar": ()}, "solar"),
        ({"strategies": ("teleport",)}, "strategies"),
        ({"limit_years": -1.0}, "limit_years"),
        ({"samples": -1}, "samples"),
        ({"horizon_years": 4.0}, "horizon_years"),
    ],
)
def test_bad_settings_name_the_field(kwargs, field) -> None:
    with pytest.raises(InputShapeError, match=field):
        DeorbitSettings(**kwargs)


def test_the_paper_swarm_suffices_under_low_activity_only_by_apogee_arcs(problem) -> None:
    # Everything the swarm carries (its torque-free impulse), flown three ways under five years
    # of low solar activity: lowering the whole orbit is not enough, apogee arcs are;
    # 105 m/s is not enough either way.
    model = DeorbitModel.from_problem(problem, DeorbitSettings())
    density = model.density(solar_case("low"))
    capacity = model.capacity_dv_m_s
    assert model.fly(capacity, density, STRATEGIES["spiral"], 200.0).reentry_years > 5.0
    assert model.fly(capacity, density, STRATEGIES["perigee"], 200.0).reentry_years < 5.0
    assert model.fly(capacity, density, STRATEGIES["perigee_narrow"], 200.0).reentry_years < 5.0
    for name in STRATEGIES:
        assert model.fly(105.0, density, STRATEGIES[name], 200.0).reentry_years > 5.0


def _spiral(model: DeorbitModel) -> Spiral:
    """The model's swarm and body for the independent spiral of the lifetime tests."""
    return Spiral(
        thrust_N=tuple(s.thrust_N for s in model.thrust.segments),
        impulse_Ns=tuple(s.impulse_Ns for s in model.thrust.segments),
        burn_area_m2=model.burn_areas_m2,
        decay_area_m2=model.decay.area_m2,
        drag_coefficient=model.decay.drag_coefficient,
        mass_kg=model.decay.mass_kg,
        exhaust_speed_m_s=model.thrust.exhaust_speed_m_s,
    )


def test_the_least_dv_matches_an_independent_spiral_with_nrlmsis_called_directly(
    problem, high_plan
) -> None:
    """High activity, lowering the whole orbit: the natural lifetime and the least Δv of the
    plan against the test's own circular decay on NRLMSIS at geodetic coordinates."""
    case = high_plan.cases[0]
    model = DeorbitModel.from_problem(problem, HIGH_SPIRAL)
    assert model.decay.area_m2 == pytest.approx(8.0) and model.decay.mass_kg == pytest.approx(668)
    altitude_km = problem.orbit.altitude_km
    assert problem.orbit.inclination_deg == INCLINATION_DEG  # the independent model's orbit
    air = Atmosphere.of(solar_case("high"))
    k = model.decay.drag_coefficient * model.decay.area_m2 / model.decay.mass_kg
    assert case.natural_lifetime_years == pytest.approx(
        lifetime_years(air, altitude_km, k), rel=5e-3
    )
    spiral = _spiral(model)
    dv = brentq(
        lambda dv: spiral.reentry_years(air, altitude_km, dv) - 5.0,
        0.0,
        high_plan.capacity_dv_m_s,
        xtol=1e-3,
    )
    assert case.deorbit_dv_m_s == pytest.approx(dv, abs=0.1)
    # On a spherical Earth the same debris needs far less (the old reading).
    flat = Atmosphere.of(solar_case("high"), spherical=True)
    assert spiral.reentry_years(flat, altitude_km, 0.6 * dv) < 5.0
