"""Campaign pieces: named bands per time bin, their envelope, cases that do not
depend on the case a worker ran before, and failed cases recorded."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from casadi_debris.campaigns import (
    Bands,
    CampaignSetup,
    CaseFailure,
    Envelope,
    Extremes,
    bin_bands,
    corner_cases,
    run_campaign,
    run_case,
)
from casadi_debris.config import default_problem_path, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.errors import CasesFailedError
from casadi_debris.guidance import scenario_reference
from casadi_debris.workflows import load_controller


def _bands(rng: np.random.Generator, n_bins: int = 4) -> Bands:
    values = rng.standard_normal((4, n_bins, 3))
    return Bands(Extremes(values[0], values[1]), Extremes(values[2], values[3]))


def test_bands_are_the_extremes_of_every_bin_by_name() -> None:
    time_s = np.arange(0.0, 3.01, 0.5)  # 7 samples, 6 torque steps, bins of 1 s
    rng = np.random.default_rng(2)
    error = rng.standard_normal((7, 3))
    torque = rng.standard_normal((6, 3))
    setup = SimpleNamespace(n_bins=3, bin_s=1.0, reference=SimpleNamespace(time_s=time_s))
    result = SimpleNamespace(time_s=time_s, error_rad=error, torque_Nm=torque)
    bands = bin_bands(setup, result)
    # Bin k holds the samples in [k, k+1) s; the last instant (3 s) joins the last bin.
    for k, rows in enumerate(([0, 1], [2, 3], [4, 5, 6])):
        assert np.array_equal(bands.error_rad.min[k], error[rows].min(axis=0))
        assert np.array_equal(bands.error_rad.max[k], error[rows].max(axis=0))
        steps = [r for r in rows if r < 6]  # a torque held from its sample on
        assert np.array_equal(bands.torque_Nm.min[k], torque[steps].min(axis=0))
        assert np.array_equal(bands.torque_Nm.max[k], torque[steps].max(axis=0))
    assert bands.n_bins == 3 and list(bands.quantities()) == ["error_rad", "torque_Nm"]


def test_bands_round_trip_through_named_arrays_and_refuse_bad_shapes() -> None:
    bands = _bands(np.random.default_rng(3))
    arrays = bands.to_arrays()
    assert sorted(arrays) == ["error_rad_max", "error_rad_min", "torque_Nm_max", "torque_Nm_min"]
    again = Bands.from_arrays(arrays)
    assert np.array_equal(again.torque_Nm.max, bands.torque_Nm.max)
    with pytest.raises(KeyError):
        Bands.from_arrays({k: v for k, v in arrays.items() if k != "error_rad_min"})
    with pytest.raises(ValueError, match=r"one shape \(n_bins, 3\)"):
        Bands.from_arrays({**arrays, "torque_Nm_min": np.zeros((4, 2))})
    with pytest.raises(ValueError, match="one shape"):
        Bands.from_arrays({**arrays, "torque_Nm_min": np.zeros((5, 3))})


def test_the_envelope_is_the_smallest_minimum_and_largest_maximum() -> None:
    rng = np.random.default_rng(4)
    cases = [_bands(rng) for _ in range(3)]
    cases[1].error_rad.min[0, 0] = np.nan  # a NaN never wins
    envelope = Envelope(np.arange(4.0))
    for bands in cases:
        envelope.add(bands)
    assert envelope.count == 3 and envelope.bands is not None
    for name in ("error_rad", "torque_Nm"):
        low = np.nanmin([c.quantities()[name].min for c in cases], axis=0)
        high = np.nanmax([c.quantities()[name].max for c in cases], axis=0)
        assert np.array_equal(envelope.bands.quantities()[name].min, low)
        assert np.array_equal(envelope.bands.quantities()[name].max, high)


def test_a_case_is_the_same_whatever_the_worker_ran_before(tmp_path: Path) -> None:
    path = tmp_path / "short.toml"
    path.write_text(
        f'extends = "{default_problem_path().parent / "paper_slew.toml"}"\n'
        'name = "short"\n[simulation]\nduration_s = 120.0\n'
    )
    problem = load_problem(path)
    model = build_model(problem)
    record, _ = load_controller(None)
    setup = CampaignSetup.create(problem, record.reduced, scenario_reference(problem), jit=False)
    corners = corner_cases(model)
    # One model for the three, as a worker keeps it for all its cases.
    alone = run_case(setup, corners[255], model=model)
    run_case(setup, corners[0], model=model)
    again = run_case(setup, corners[255], model=model)
    one, two = alone.bands.to_arrays(), again.bands.to_arrays()
    assert all(np.array_equal(one[k], two[k]) for k in one)
    assert alone.summary.run.fuel_per_cubesat_kg == again.summary.run.fuel_per_cubesat_kg


def test_a_failed_case_is_recorded_and_the_campaign_goes_on(tmp_path: Path) -> None:
    path = tmp_path / "short.toml"
    path.write_text(
        f'extends = "{default_problem_path().parent / "paper_slew.toml"}"\n'
        'name = "short"\n[simulation]\nduration_s = 30.0\n'
    )
    problem = load_problem(path)
    model = build_model(problem)
    record, _ = load_controller(None)
    setup = CampaignSetup.create(problem, record.reduced, scenario_reference(problem), jit=False)
    corners = corner_cases(model)
    # A plant that goes non-finite: its torque demand is refused by the allocator.
    broken = dataclasses.replace(corners[1], parameters=np.full_like(corners[1].parameters, np.nan))
    cases = [corners[0], broken, corners[2]]
    failures: list[CaseFailure] = []
    done = run_campaign(setup, cases, workers=2, on_failure=failures.append)
    assert [o.case.case_id for o in done] == ["corner-0000", "corner-0002"]
    assert [f.case.case_id for f in failures] == ["corner-0001"]
    assert failures[0].error_type.endswith("DemandError") and "finite" in failures[0].message
    assert "Traceback" in failures[0].traceback
    assert failures[0].summary().identity.case_id == "corner-0001"
    # Without a place for failures, they are raised once every other case has finished.
    seen: list[str] = []
    with pytest.raises(CasesFailedError, match="corner-0001") as raised:
        run_campaign(setup, cases, workers=1, on_result=lambda o: seen.append(o.case.case_id))
    assert seen == ["corner-0000", "corner-0002"]
    assert [f.case.case_id for f in raised.value.failures] == ["corner-0001"]
