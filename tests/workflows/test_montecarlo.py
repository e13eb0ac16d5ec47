"""``casadi_debris.montecarlo`` is ``casadi-debris montecarlo``: the same summary, the
same folder, its cases as an xarray Dataset, its figures."""

from __future__ import annotations

import json
import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main
from casadi_debris.store import open_campaign
from workflow_files import files_written as _files
from workflow_files import short_problem as _short


def _without_out_dir(record: dict) -> dict:
    return {k: v for k, v in record.items() if k != "out_dir"}


def _cli_json(args: list[str]) -> dict:
    result = CliRunner().invoke(main, ["montecarlo", *args, "--json"], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


# The paper's slew (corners, spread) and a campaign of [[montecarlo.vary]] draws, whose
# cases change the problem file's own values (the star tracker, the disturbance).
CAMPAIGNS = [
    ("paper_slew", 40.0, ["--max-cases", "2"], {"max_cases": 2}),
    # A campaign of [[montecarlo.vary]] keys: under -m slow (20 s; the default run keeps
    # the plain one, and test_cli_simulation flies the varied campaign from the command).
    pytest.param(
        "paper_slew_dispersions",
        30.0,
        ["--samples", "2", "--seed", "5"],
        {"samples": 2, "seed": 5},
        marks=pytest.mark.slow,
    ),
]


@pytest.mark.parametrize(("base", "duration_s", "flags", "keywords"), CAMPAIGNS)
def test_python_and_the_command_line_run_the_same_campaign(
    base: str, duration_s: float, flags: list[str], keywords: dict, tmp_path: Path
) -> None:
    problem_file = _short(tmp_path, base, duration_s)
    calls: list[tuple[int, int]] = []
    result = cd.montecarlo(
        problem_file, workers=1, progress=lambda d, t: calls.append((d, t)), **keywords
    )
    assert calls == [(0, 2), (1, 2), (2, 2)]
    assert result.summary.run.out_dir is None
    assert list(tmp_path.iterdir()) == [problem_file]  # nothing written without a folder

    folder = tmp_path / "cli"
    printed = _cli_json([str(problem_file), *flags, "--workers", "1", "--out", str(folder)])
    assert printed["out_dir"] == str(folder.absolute())
    ours = json.loads(json.dumps(result.summary.to_json()))
    assert _without_out_dir(ours) == _without_out_dir(printed)

    # The worst case and the dataset, against the cases' own figures.
    fuels = [o.summary.run.fuel_kg for o in result.outcomes]
    assert result.summary.worst["fuel_kg"].value == max(fuels)
    dataset = result.dataset
    assert list(dataset["case"].values) == [o.case.case_id for o in result.outcomes]
    np.testing.assert_array_equal(dataset["fuel_kg"].values, fuels)

    saved = result.save(tmp_path / "saved")
    assert _files(saved) == _files(folder)
    summary = json.loads((saved / "summary.json").read_text())
    assert summary["out_dir"] == str(saved.absolute())
    assert _without_out_dir(summary) == _without_out_dir(printed)
    assert (saved / "cases.csv").read_text() == (folder / "cases.csv").read_text()
    with open_campaign(saved) as written, open_campaign(folder) as by_command:
        np.testing.assert_array_equal(written["fuel_kg"].values, fuels)
        np.testing.assert_array_equal(written["error_rad"].values, by_command["error_rad"].values)
    with pytest.raises(cd.CasadiDebrisError, match="exists"):
        result.save(saved)  # never over a folder without overwrite

    figures = result.plot()
    try:
        pngs = {p.removesuffix(".png") for p in _files(saved) if p.endswith(".png")}
        assert set(figures) == pngs
        assert all(f.axes for f in figures.values())
    finally:
        for figure in figures.values():
            plt.close(figure)


def test_a_campaign_given_a_folder_writes_it_as_it_goes(tmp_path: Path) -> None:
    problem_file = _short(tmp_path, "paper_slew", 30.0)
    out = tmp_path / "mc"
    result = cd.montecarlo(problem_file, max_cases=1, workers=1, out=out, no_jit=True)
    assert result.summary.run.out_dir == str(out.absolute())
    assert not result.summary.run.compiled_step
    assert json.loads((out / "summary.json").read_text()) == json.loads(
        json.dumps(result.summary.to_json())
    )
    assert "cases/corner-0000.npz" in _files(out)
    assert sorted(os.listdir(tmp_path)) == ["mc", problem_file.name]
