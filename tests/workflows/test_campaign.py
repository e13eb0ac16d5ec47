"""A campaign from Python, without the command line: cases, progress, the folder."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from casadi_debris.config import default_controller_path, default_problem_path, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.errors import InputShapeError
from casadi_debris.report import CampaignSummary
from casadi_debris.workflows import CaseSelection, check_scheduler_address, montecarlo, one_case


@pytest.fixture(scope="module")
def short_slew(tmp_path_factory: pytest.TempPathFactory):
    path = tmp_path_factory.mktemp("problems") / "short.toml"
    path.write_text(
        f'extends = "{default_problem_path().parent / "paper_slew.toml"}"\n'
        'name = "short"\n[simulation]\nduration_s = 60.0\n'
    )
    problem = load_problem(path)
    return problem, build_model(problem)


def test_selection_spreads_max_cases_over_the_corners(short_slew) -> None:
    _, model = short_slew
    every = CaseSelection(corners=True).cases(model)
    assert len(every) == 256
    few = CaseSelection(max_cases=5).cases(model)
    assert [c.case_id for c in few] == [every[i].case_id for i in (0, 64, 128, 191, 255)]
    with pytest.raises(InputShapeError, match="either --corners or --samples"):
        CaseSelection(corners=True, samples=3).cases(model)
    samples = CaseSelection(samples=3, seed=7).cases(model)
    assert [(c.kind, c.seed) for c in samples] == [("sample", 7)] * 3


def test_one_case_names_the_option_it_came_from(short_slew) -> None:
    _, model = short_slew
    assert one_case(model, None, None, None).case_id == "nominal"
    assert one_case(model, 3, None, None).case_id == "corner-0003"
    with pytest.raises(InputShapeError, match=r"^--corner: "):
        one_case(model, 999, None, None)


@pytest.mark.parametrize(
    "address", ["tcp://10.0.0.1:8786", "tls://host.example:1", "tcp://[::1]:2"]
)
def test_scheduler_addresses_of_dask_transports_pass(address: str) -> None:
    check_scheduler_address(address)


def test_a_campaign_runs_from_python_and_reports_progress(short_slew, tmp_path: Path) -> None:
    problem, _ = short_slew
    calls: list[tuple[int, int]] = []
    summary = montecarlo(
        problem,
        samples=2,
        seed=3,
        out=tmp_path / "mc",
        workers=1,
        progress=lambda done, total: calls.append((done, total)),
    ).summary
    assert calls == [(0, 2), (1, 2), (2, 2)]
    assert summary.cases == 2 and summary.run.seed == 3
    written = json.loads((tmp_path / "mc" / "summary.json").read_text())
    assert written == json.loads(json.dumps(summary.to_json()))
    assert CampaignSummary.from_json(written).worst == summary.worst
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mc"]


def test_a_campaign_in_a_staging_folder_records_its_final_paths(short_slew, tmp_path: Path):
    problem, _ = short_slew
    staging, final = tmp_path / ".report.new", tmp_path / "report"
    controller = staging / "controller.json"
    staging.mkdir()
    controller.write_bytes(default_controller_path().read_bytes())
    summary = montecarlo(
        problem,
        controller=controller,
        samples=1,
        seed=3,
        out=staging / "slew",
        workers=1,
        moved_to=(staging, final),
    ).summary
    assert summary.run.out_dir == str((final / "slew").absolute())
    assert summary.run.controller_path == str((final / "controller.json").absolute())
    nominal = json.loads((staging / "slew" / "nominal" / "summary.json").read_text())
    assert nominal["controller_path"] == summary.run.controller_path
