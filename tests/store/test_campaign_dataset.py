"""campaign.nc: the dataset's dimensions, coordinates and units, written whole, opened back
bit for bit with plain xarray and with open_campaign."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from casadi_debris.campaigns import (
    Bands,
    Case,
    CaseResult,
    CaseSummary,
    Extremes,
    campaign_dataset,
)
from casadi_debris.store import (
    CASE_FIGURES,
    DATASET_NAME,
    NO_SEED,
    CampaignIdentity,
    open_campaign,
    write_campaign_dataset,
)
from run_summaries import zero_run_summary

PARAMETERS = ("p1", "p2", "p3", "p4", "p5", "p6")
N_BINS = 5


def _outcome(index: int, rng: np.random.Generator, seed: int | None) -> CaseResult:
    kind = "corner" if seed is None else "sample"
    case = Case(f"{kind}-{index:04d}", kind, index, seed, rng.uniform(-1, 1, 6), np.ones(6))
    values = rng.standard_normal((4, N_BINS, 3)) * 1e-7
    figures = {name: float(rng.uniform()) for name in CASE_FIGURES}
    figures["settle_time_s"] = None  # never settled: NaN in the dataset, empty in cases.csv
    run = zero_run_summary(
        **figures,
        max_torque_mNm=tuple(rng.uniform(size=3)),
        fuel_per_cubesat_kg=tuple(rng.uniform(size=24)),
    )
    bands = Bands(Extremes(values[0], values[1]), Extremes(values[2], values[3]))
    return CaseResult(case, CaseSummary(case.identity(), run), bands)


def _record(seed: int | None, ids: list[str]) -> CampaignIdentity:
    return CampaignIdentity(
        problem_name="paper_slew",
        problem_sha256="a" * 64,
        controller_sha256="b" * 64,
        case_kind="corner" if seed is None else "sample",
        seed=seed,
        case_ids=tuple(ids),
        envelope_bin_s=2.0,
    )


def _dataset(seed: int | None = None, count: int = 3) -> tuple[xr.Dataset, list[CaseResult]]:
    rng = np.random.default_rng(8)
    outcomes = [_outcome(i, rng, seed) for i in range(count)]
    record = _record(seed, [o.case.case_id for o in outcomes])
    bin_start_s = 10.0 + 2.0 * np.arange(N_BINS)
    return campaign_dataset(record, bin_start_s, outcomes, PARAMETERS), outcomes


def test_dimensions_coordinates_and_units() -> None:
    ds, _ = _dataset()
    assert dict(ds.sizes) == {
        "case": 3,
        "time": N_BINS,
        "bound": 2,
        "axis": 3,
        "parameter": 6,
        "cubesat": 24,
        "varied": 6,
    }
    assert list(ds.case.values) == ["corner-0000", "corner-0001", "corner-0002"]
    assert list(ds.bound.values) == ["min", "max"] and list(ds.axis.values) == ["x", "y", "z"]
    assert list(ds.cubesat.values) == list(range(1, 25))  # numbered from 1
    assert ds.time.attrs["units"] == "s" and ds.time.values[0] == 10.0
    assert ds.error_rad.dims == ("case", "time", "bound", "axis")
    assert ds.error_rad.attrs["units"] == "rad" and ds.torque_Nm.attrs["units"] == "N m"
    for name, (units, _) in CASE_FIGURES.items():
        assert ds[name].dims == ("case",) and ds[name].attrs["units"] == units
    assert ds.max_torque_mNm.dims == ("case", "axis")
    assert ds.normalized.dims == ("case", "parameter") and list(ds.parameter.values) == list(
        PARAMETERS
    )
    assert set(ds.coords) >= {"kind", "index", "seed", "normalized"}
    assert (ds.seed == NO_SEED).all() and ds.attrs["seed"] == NO_SEED
    assert ds.attrs["problem"] == "paper_slew" and ds.attrs["bin_width_s"] == 2.0
    assert ds.attrs["problem_sha256"] == "a" * 64 and ds.attrs["controller_sha256"] == "b" * 64
    assert ds.settle_time_s.isnull().all()


def test_values_are_the_outcomes_bits_by_name() -> None:
    ds, outcomes = _dataset(seed=11)
    for outcome in outcomes:
        one = ds.sel(case=outcome.case.case_id)
        for name, extremes in outcome.bands.quantities().items():
            for bound in ("min", "max"):
                stored = one[name].sel(bound=bound).values
                assert np.array_equal(stored, getattr(extremes, bound)), (name, bound)
        assert one.fuel_kg.item() == outcome.summary.run.fuel_kg
        assert one.seed.item() == 11 and one.kind.item() == "sample"
        assert np.array_equal(one.normalized.values, outcome.case.normalized)
        assert tuple(one.fuel_per_cubesat_kg.values) == outcome.summary.run.fuel_per_cubesat_kg
    # Different units, so one variable each; one dimension for both on demand.
    stacked = ds[["error_rad", "torque_Nm"]].to_dataarray("quantity")
    assert stacked.dims == ("quantity", "case", "time", "bound", "axis")


def test_written_whole_and_opened_back_identical(tmp_path: Path) -> None:
    ds, _ = _dataset()
    path = write_campaign_dataset(tmp_path / DATASET_NAME, ds)
    assert sorted(p.name for p in tmp_path.iterdir()) == [DATASET_NAME]  # no temporary left
    with xr.open_dataset(path) as plain, open_campaign(tmp_path) as ours:
        assert plain.identical(ours)
        assert ours.identical(ds.load())
        assert ours.error_rad.encoding["zlib"] and ours.error_rad.encoding["chunksizes"][0] == 1
    with open_campaign(path) as by_file:
        assert by_file.sel(case="corner-0001").fuel_kg.item() == ds.fuel_kg.values[1]


def test_a_failed_write_leaves_nothing(tmp_path: Path) -> None:
    ds, _ = _dataset()
    ds.attrs["not storable"] = {"a": 1}  # netCDF attributes hold no dicts
    with pytest.raises((TypeError, ValueError)):
        write_campaign_dataset(tmp_path / DATASET_NAME, ds)
    assert list(tmp_path.iterdir()) == []


def test_open_campaign_names_what_is_missing(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="written when every case of a campaign is done"):
        open_campaign(tmp_path)
    xr.Dataset({"x": ("t", [1.0])}).to_netcdf(tmp_path / DATASET_NAME, engine="h5netcdf")
    with pytest.raises(ValueError, match="not a casadi_debris campaign"):
        open_campaign(tmp_path)


def test_an_empty_campaign_is_refused() -> None:
    with pytest.raises(ValueError, match="at least one case"):
        campaign_dataset(_record(None, []), np.arange(3.0), [], PARAMETERS)


def test_a_varied_campaign_keeps_every_cases_seed_and_values_by_name(tmp_path: Path) -> None:
    rng = np.random.default_rng(4)
    names = ("environment.density_kg_m3", "mass_kg")
    values = rng.uniform(size=(4, 2))
    outcomes = []
    for i, row in enumerate(values):
        plain = _outcome(i, rng, 11)
        case = Case(
            f"varied-{i:04d}",
            "varied",
            i,
            11,
            plain.case.normalized,
            plain.case.parameters,
            varied=tuple(zip(names, row.tolist(), strict=True)),
        )
        outcomes.append(
            CaseResult(case, CaseSummary(case.identity(), plain.summary.run), plain.bands)
        )
    record = _record(11, [o.case.case_id for o in outcomes])
    path = write_campaign_dataset(
        tmp_path / DATASET_NAME,
        campaign_dataset(record, 2.0 * np.arange(N_BINS), outcomes, PARAMETERS),
    )
    with open_campaign(path) as ds:
        assert list(ds.varied.values) == list(names)
        assert np.array_equal(ds.varied_value.values, values)
        assert ds.varied_value.sel(case="varied-0002", varied="mass_kg").item() == values[2, 1]
        assert list(ds.seed.values) == [11] * 4
    # The case's own record (cases/<id>.json) names its values too.
    assert outcomes[3].summary.to_json()["varied"] == dict(zip(names, values[3], strict=True))


def test_a_campaign_over_the_uncertainty_set_varies_the_model_parameters() -> None:
    ds, outcomes = _dataset()
    assert list(ds.varied.values) == list(PARAMETERS)
    assert np.array_equal(ds.varied_value.values, [o.case.parameters for o in outcomes])
