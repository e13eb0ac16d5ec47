"""``casadi_debris.worstcase`` is ``casadi-debris worstcase``: the same summary, the same
folder, the worst run's figure."""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib.pyplot as plt
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main
from workflow_files import files_written as _files
from workflow_files import short_problem as _short


def _comparable(record: dict) -> dict:
    """A summary without what differs between two runs: the folder and the stages' wall
    times."""
    kept = {k: v for k, v in record.items() if k != "out_dir"}
    for stage in ("search", "mu"):
        if stage in kept:
            kept[stage] = {k: v for k, v in kept[stage].items() if k != "time_s"}
    return kept


# The paper's slew searched, a debris with one array (the shipped controller flown on it
# anyway) searched too, and the mu bounds on one array angle (minutes: under -m slow).
RUNS = [
    ("paper_slew", ["--no-mu", "--budget", "2"], {"no_mu": True, "budget": 2}),
    (
        "gallery/one_array",
        ["--no-mu", "--budget", "2", "--allow-mismatch"],
        {"no_mu": True, "budget": 2, "allow_mismatch": True},
    ),
    pytest.param(
        "gallery/one_array",
        ["--no-search", "--angles", "1", "--allow-mismatch"],
        {"no_search": True, "angles": 1, "allow_mismatch": True},
        marks=pytest.mark.slow,
    ),
]


@pytest.mark.parametrize(("base", "flags", "keywords"), RUNS)
def test_python_and_the_command_line_find_the_same_worst_cases(
    base: str, flags: list[str], keywords: dict, tmp_path: Path
) -> None:
    problem_file = _short(tmp_path, base, 40.0)
    stages: list[str] = []
    result = cd.worstcase(problem_file, progress=lambda stage: stages.append(stage), **keywords)
    assert result.summary.identity.out_dir is None
    assert stages == (["worst-case search"] if result.mu is None else ["real-parametric mu"])

    folder = tmp_path / "cli"
    command = CliRunner().invoke(
        main,
        ["worstcase", str(problem_file), *flags, "--out", str(folder), "--json"],
        catch_exceptions=False,
    )
    assert command.exit_code == 0, command.output
    printed = json.loads(command.stdout)
    assert _comparable(json.loads(json.dumps(result.summary.to_json()))) == _comparable(printed)

    saved = result.save(tmp_path / "saved")
    assert _files(saved) == _files(folder)
    written = json.loads((saved / "summary.json").read_text())
    assert written["out_dir"] == str(saved.absolute())
    assert _comparable(written) == _comparable(printed)

    if result.search is not None:
        # The summary's worst is the largest error of the search's own runs.
        errors = [e.max_error_deg for e in result.search.evaluations]
        assert result.summary.search is not None
        assert result.summary.search.max_error_deg == max(errors)
    else:
        # The summary's peaks are those of the bounds over the angle and frequency grid.
        assert result.mu is not None and result.summary.mu is not None
        for kind in ("stability", "performance"):
            bounds = getattr(result.mu, kind)
            shown = getattr(result.summary.mu, kind)
            assert shown.mu_upper == float(bounds.upper.max())
            assert shown.mu_lower == float(bounds.lower.max()) <= shown.mu_upper

    figures = result.plot()
    try:
        assert set(figures) == {p.removesuffix(".png") for p in _files(saved) if p.endswith(".png")}
    finally:
        for figure in figures.values():
            plt.close(figure)
