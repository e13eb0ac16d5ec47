"""The worst-case folder's records: the corner campaign a search is compared with, read
from its campaign.nc, and the one JSON form of summary.json and the parameters files."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from casadi_debris import load_problem
from casadi_debris.campaigns import (
    Bands,
    Case,
    CaseResult,
    CaseSummary,
    Extremes,
    campaign_dataset,
)
from casadi_debris.dynamics import build_model
from casadi_debris.report import (
    ParameterFile,
    WorstCaseIdentity,
    WorstCaseSummary,
    corner_campaign_envelope,
    parameter_file,
    write_worst_cases,
)
from casadi_debris.robust.mu import WorstPerturbation
from casadi_debris.robust.plant import parameters_from_normalized
from casadi_debris.store import CASE_FIGURES, DATASET_NAME, CampaignIdentity, write_campaign_dataset
from run_summaries import zero_run_summary

N_BINS = 4
IDENTITY_KEYS = {
    "problem", "problem_sha256", "plant_sha256", "controller_path", "controller_plant_sha256",
    "out_dir",
}  # fmt: skip


def _campaign(folder: Path, errors_deg: list[float]) -> list[CaseResult]:
    """A corner campaign.nc whose cases reach ``errors_deg``, with random bands."""
    rng = np.random.default_rng(5)
    outcomes = []
    for index, error in enumerate(errors_deg):
        case = Case(f"corner-{index:04d}", "corner", index, None, rng.uniform(-1, 1, 6), np.ones(6))
        figures = {name: 0.0 for name in CASE_FIGURES} | {"max_error_deg": error}
        run = zero_run_summary(
            **figures, max_torque_mNm=(0.0,) * 3, fuel_per_cubesat_kg=(0.0,) * 24
        )
        values = rng.standard_normal((4, N_BINS, 3))
        bands = Bands(Extremes(values[0], values[1]), Extremes(values[2], values[3]))
        outcomes.append(CaseResult(case, CaseSummary(case.identity(), run), bands))
    ids = tuple(o.case.case_id for o in outcomes)
    record = CampaignIdentity("paper_slew", "a" * 64, "b" * 64, "corner", None, ids, 2.0)
    names = tuple(f"p{i}" for i in range(6))
    dataset = campaign_dataset(record, 2.0 * np.arange(N_BINS), outcomes, names)
    write_campaign_dataset(folder / DATASET_NAME, dataset)
    return outcomes


def _identity(out: Path) -> WorstCaseIdentity:
    return WorstCaseIdentity("paper", "c" * 64, "d" * 64, "/c.json", "d" * 64, str(out))


def test_the_campaign_worst_and_envelope_come_from_its_cases(tmp_path: Path) -> None:
    campaign = tmp_path / "campaign"
    campaign.mkdir()
    _campaign(campaign, [0.3, 0.61, 0.2, 0.61])
    out = tmp_path / "wc"
    out.mkdir()
    problem = load_problem()
    summary = write_worst_cases(out, build_model(problem), _identity(out), None, None, campaign)
    written = json.loads((out / "summary.json").read_text())
    # No mu, no search: their keys are absent, not null.
    assert set(written) == IDENTITY_KEYS | {"campaign"}
    assert written["campaign"] == {
        "folder": str(campaign.absolute()),
        "cases": 4,
        "worst_max_error_deg": 0.61,
        "worst_cases": ["corner-0001", "corner-0003"],
    }
    assert WorstCaseSummary.from_json(written) == summary
    assert summary.to_json() == written
    assert summary.mu is None and summary.search is None


def test_the_envelope_bounds_every_case(tmp_path: Path) -> None:
    outcomes = _campaign(tmp_path, [0.1, 0.2, 0.3])
    envelope, worst = corner_campaign_envelope(tmp_path)
    lows = np.array([o.bands.error_rad.min for o in outcomes])
    highs = np.array([o.bands.error_rad.max for o in outcomes])
    # campaign.nc stores the bands as float32: compared at that precision.
    np.testing.assert_allclose(envelope.bands.error_rad.min, lows.min(axis=0), rtol=1e-6)
    np.testing.assert_allclose(envelope.bands.error_rad.max, highs.max(axis=0), rtol=1e-6)
    assert worst.worst_cases == ("corner-0002",) and worst.cases == 3


@pytest.mark.parametrize("kind", ["search", "mu"])
def test_a_parameters_file_holds_what_its_kind_says(kind: str) -> None:
    problem = load_problem()
    model = build_model(problem)
    layout = model.parameter_layout
    normalized = np.linspace(-1.0, 1.0, layout.size)
    values = parameters_from_normalized(model, normalized)
    if kind == "search":
        record = parameter_file(layout, normalized, values, "worstcase", max_error_deg=0.5)
        extra = {"max_error_deg"}
    else:
        unclipped = 1.5 * normalized
        worst = WorstPerturbation(0.7, 0.02, 0, np.eye(2), 0.0, unclipped, normalized)
        record = parameter_file(layout, normalized, values, "mu-stability", perturbation=worst)
        extra = {"clipped", "normalized_unclipped", "mu_lower", "omega_rad_s"}
        assert record.clipped is True and record.mu_lower == 0.7
        assert list(record.normalized_unclipped.values()) == unclipped.tolist()
    data = json.loads(json.dumps(record.to_json()))
    assert set(data) == {"case_id", "parameters", "normalized"} | extra
    assert list(data["parameters"]) == list(layout.names)
    assert list(data["parameters"].values()) == pytest.approx(values.tolist(), rel=1e-15)
    assert list(data["normalized"].values()) == normalized.tolist()
    assert ParameterFile.from_json(data) == record
