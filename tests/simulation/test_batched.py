"""Campaign cases run together (one compiled function mapped over them) give the numbers
each gives alone: on CasADi's virtual machine (constants folded, another graph), alone
compiled, and through ``simulate`` with the same failures."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris.allocation import Allocator
from casadi_debris.campaigns import CampaignSetup, CaseFailure, batches, corner_cases, run_campaign
from casadi_debris.cli import main
from casadi_debris.config import FailureEvent, default_problem_path, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.simulation import (
    LoopSettings,
    RunInputs,
    c_compiler,
    discretize_controller,
    simulate_closed_loop,
    simulate_many,
)
from casadi_debris.simulation import _jit_cache as jit_cache
from casadi_debris.simulation._batched import facet_capacity, facet_rows
from casadi_debris.simulation._closed_loop import _loop_step
from casadi_debris.simulation._native import NativeFunction
from casadi_debris.workflows import load_controller

pytestmark = pytest.mark.skipif(c_compiler() is None, reason="no C compiler for CasADi's JIT")

CORNERS = (0, 142, 255)  # 142: the paper's worst slew corner


@pytest.fixture(scope="module")
def module_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("jit_cache")


@pytest.fixture(autouse=True)
def _private_cache(module_cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(jit_cache.CACHE_ENV, str(module_cache))


@pytest.fixture(scope="module")
def short_slew(tmp_path_factory: pytest.TempPathFactory):
    """The paper's slew cut to its first 200 s (the bang-bang's first half saturates)."""
    path = tmp_path_factory.mktemp("problem") / "short.toml"
    path.write_text(
        f'extends = "{default_problem_path().parent / "paper_slew.toml"}"\n'
        'name = "short"\n[simulation]\nduration_s = 200.0\n'
    )
    problem = load_problem(path)
    return path, problem, build_model(problem), load_controller(None)[0].reduced


def _fresh(problem, model) -> Allocator:
    return Allocator.from_problem(problem, model.geometry)


def test_batched_corners_equal_their_runs_alone(short_slew) -> None:
    _, problem, model, controller = short_slew
    reference = scenario_reference(problem)
    corners = [corner_cases(model)[i] for i in CORNERS]
    # The last corner with CubeSats 1 and 2 failed at 20 s: its torque saturates.
    failures = [(), (), tuple(FailureEvent(time_s=20.0, cubesat=i, stage=None) for i in (0, 1))]
    together = simulate_many(
        model,
        controller,
        reference,
        [
            RunInputs(c.parameters, failed, _fresh(problem, model))
            for c, failed in zip(corners, failures, strict=True)
        ],
        settings=LoopSettings(jit=True),
        slots=4,  # one slot left unused
    )
    for corner, failed, batched in zip(corners, failures, together, strict=True):
        assert not isinstance(batched, Exception)
        assert batched.compiled_step
        alone = simulate_closed_loop(
            model,
            controller,
            reference,
            parameters=corner.parameters,
            failures=failed,
            allocator=_fresh(problem, model),
            settings=LoopSettings(jit=True),
        )
        # The same C on the same inputs, slot or alone: the same bits.
        assert np.array_equal(batched.state, alone.state)
        assert np.array_equal(batched.thrust_N, alone.thrust_N)
        # CasADi's virtual machine with the authority folded in as constants: round-off.
        folded = simulate_closed_loop(
            model,
            controller,
            reference,
            parameters=corner.parameters,
            failures=failed,
            allocator=_fresh(problem, model),
        )
        assert not folded.compiled_step
        assert np.abs(folded.state - batched.state).max() < 1e-12
        assert np.abs(folded.thrust_N - batched.thrust_N).max() < 1e-15
        assert batched.summary().fuel_kg == pytest.approx(folded.summary().fuel_kg, rel=1e-12)
    last = together[-1]
    assert not isinstance(last, Exception)
    assert last.scale.min() < 1.0 and len(last.authority_time_s) == 2


def test_a_batched_campaign_gives_each_case_as_run_alone(short_slew) -> None:
    _, problem, model, controller = short_slew
    corners = [corner_cases(model)[i] for i in CORNERS]
    reference = scenario_reference(problem)
    one_by_one = CampaignSetup.create(problem, controller, reference, jit=False)
    batched = dataclasses.replace(one_by_one, jit=True, batch_cases=4)
    assert batched.batched and not one_by_one.batched
    alone = {o.case.case_id: o for o in run_campaign(one_by_one, corners)}
    together = run_campaign(batched, corners, workers=2)
    assert [o.case.case_id for o in together] == [c.case_id for c in corners]
    for outcome in together:
        run, reference_run = outcome.summary.run, alone[outcome.case.case_id].summary.run
        assert run.max_error_deg == pytest.approx(reference_run.max_error_deg, rel=1e-10)
        assert run.fuel_kg == pytest.approx(reference_run.fuel_kg, rel=1e-12)
        for name, bands in outcome.bands.to_arrays().items():
            other = alone[outcome.case.case_id].bands.to_arrays()[name]
            assert np.allclose(bands, other, rtol=1e-9, atol=1e-15)


def test_a_failure_case_batched_equals_simulate_with_its_failures(short_slew) -> None:
    path, problem, model, controller = short_slew
    failed = (0, 1)  # CubeSats 1 and 2: the slew saturates from the start
    events = tuple(FailureEvent(time_s=0.0, cubesat=i, stage=None) for i in failed)
    corner = corner_cases(model)[0]
    plants = [dataclasses.replace(corner, case_id=f"failed-{i}", failures=events) for i in (1, 2)]
    plants[1] = dataclasses.replace(plants[1], failures=())  # the whole swarm beside it
    setup = CampaignSetup.create(problem, controller, scenario_reference(problem), batch_cases=2)
    together = {o.case.case_id: o.summary.run for o in run_campaign(setup, plants)}
    answer = CliRunner().invoke(
        main,
        ["simulate", str(path), "--failed", "1,2", "--json", "--out", str(path.parent / "run")],
    )
    assert answer.exit_code == 0, answer.output
    alone = json.loads(answer.stdout)
    # simulate flies the nominal plant; the corner here is another: fly it alone too.
    direct = simulate_closed_loop(
        model,
        controller,
        scenario_reference(problem),
        parameters=corner.parameters,
        failures=events,
        allocator=_fresh(problem, model),
    ).summary()
    assert together["failed-1"].max_error_deg == pytest.approx(direct.max_error_deg, rel=1e-10)
    assert together["failed-1"].fuel_per_cubesat_kg == pytest.approx(
        direct.fuel_per_cubesat_kg, rel=1e-10, abs=1e-18
    )
    # The failed CubeSats burn nothing; the whole swarm's do.
    assert together["failed-1"].fuel_per_cubesat_kg[:2] == (0.0, 0.0)
    assert min(together["failed-2"].fuel_per_cubesat_kg[:2]) > 0.0
    assert together["failed-1"].torque_saturated_s > together["failed-2"].torque_saturated_s
    nominal = dataclasses.replace(plants[0], parameters=model.nominal_parameters)
    on_nominal = run_campaign(setup, [nominal, plants[1]])[0].summary.run
    summary = alone.get("summary", alone)
    assert on_nominal.max_error_deg == pytest.approx(summary["max_error_deg"], rel=1e-10)
    assert on_nominal.fuel_kg == pytest.approx(summary["fuel_kg"], rel=1e-10)


def test_a_case_that_raises_in_a_batch_is_recorded_and_the_others_go_on(short_slew) -> None:
    _, problem, model, controller = short_slew
    corners = corner_cases(model)[:3]
    every = tuple(
        FailureEvent(time_s=10.0, cubesat=i, stage=None) for i in range(len(problem.cubesats))
    )
    cases = [corners[0], dataclasses.replace(corners[1], failures=every), corners[2]]
    setup = CampaignSetup.create(problem, controller, scenario_reference(problem), batch_cases=4)
    failures: list[CaseFailure] = []
    done = run_campaign(setup, cases, on_failure=failures.append)
    assert [o.case.case_id for o in done] == [corners[0].case_id, corners[2].case_id]
    assert [f.case.case_id for f in failures] == [corners[1].case_id]
    assert "NoEngineError" in failures[0].error_type and "Traceback" in failures[0].traceback


def test_padded_facets_give_the_folded_step(short_slew) -> None:
    _, problem, model, controller = short_slew
    discrete = discretize_controller(controller, 0.1)
    polytope = _fresh(problem, model).authority_polytope()
    folded = _loop_step(model, None, discrete, polytope, 2, "rk4")
    capacity = facet_capacity([polytope])
    generic = _loop_step(model, None, discrete, capacity, 2, "rk4")
    rng = np.random.default_rng(3)
    z = np.concatenate([model.initial_state(), rng.normal(0.0, 1.0, discrete.n_states)])
    s = np.array([12.0, *(q := rng.normal(size=4)) / np.linalg.norm(q), 0.0, 0.0, 0.0])
    p = model.nominal_parameters
    want = folded(z, s, p)
    got = generic(z, s, p, facet_rows(polytope, capacity))
    assert float(want[1][3]) < 1.0  # a random attitude error saturates the torque
    for a, b in zip(want, got, strict=True):
        assert np.array_equal(np.asarray(a), np.asarray(b))


def test_native_function_matches_casadi() -> None:
    x = ca.SX.sym("x", 3, 2)
    y = ca.SX.sym("y", 2)
    f = ca.Function("small_native", [x, y], [ca.sin(x) @ y, ca.vertcat(y, ca.sum1(x).T) * 2])
    native = NativeFunction(f, jit_cache.compiled_library(f, c_compiler()))
    rng = np.random.default_rng(5)
    xv, yv = rng.normal(size=(3, 2)), rng.normal(size=2)
    got = native.call([xv.T, yv])  # column-major: (columns, rows)
    want = f(xv, yv)
    assert np.allclose(got[0].T, np.asarray(want[0]), rtol=1e-14, atol=0)
    assert np.allclose(got[1].T, np.asarray(want[1]), rtol=1e-14, atol=0)
    with pytest.raises(ValueError, match="expected 3 x 2"):
        native.call([np.zeros(5), yv])


def test_batches_fill_power_of_two_slots(short_slew) -> None:
    _, _, model, _ = short_slew
    cases = corner_cases(model)
    made = batches(cases[:37], 16, workers=2)
    assert {b.slots for b in made} == {16} and [len(b.cases) for b in made] == [16, 16, 5]
    assert [c for b in made for c in b.cases] == cases[:37]
    assert [b.slots for b in batches(cases[:5], 16, workers=2)] == [4, 4]
    assert [len(b.cases) for b in batches(cases[:3], 16, workers=2)] == [2, 1]
    assert [b.slots for b in batches(cases[:3], 1, workers=1)] == [1, 1, 1]
