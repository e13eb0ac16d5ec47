"""``casadi_debris.failures`` is ``casadi-debris failures``: the same summary, the same
folder, the heat map."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import matplotlib.pyplot as plt
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main
from casadi_debris.config import default_problem_path
from workflow_files import files_written as _files

PROBLEMS = default_problem_path().parent


def _comparable(record: dict) -> dict:
    """A summary without what differs between two runs: the folder and the wall time."""
    return {k: v for k, v in record.items() if k not in {"out_dir", "wall_time_s"}}


# The paper's swarm (single failures and lost stages), and three faces of CubeSats with
# every pair failed and no lost stage.
RUNS = [
    (PROBLEMS / "paper.toml", ["--max-failed", "1"], {"max_failed": 1}, True),
    (
        PROBLEMS / "gallery" / "three_faces.toml",
        ["--max-failed", "2", "--no-stages"],
        {"max_failed": 2, "stages": False},
        False,
    ),
]


@pytest.mark.parametrize(("problem_file", "flags", "keywords", "stages"), RUNS)
def test_python_and_the_command_line_study_the_same_failures(
    problem_file: Path, flags: list[str], keywords: dict, stages: bool, tmp_path: Path
) -> None:
    result = cd.failures(problem_file, closed_loop=False, **keywords)
    assert result.summary.out_dir is None

    folder = tmp_path / "cli"
    args = [str(problem_file), *flags, "--no-closed-loop", "--out", str(folder), "--json"]
    command = CliRunner().invoke(main, ["failures", *args], catch_exceptions=False)
    assert command.exit_code == 0, command.output
    printed = json.loads(command.stdout)
    assert _comparable(json.loads(json.dumps(result.summary.to_json()))) == _comparable(printed)

    # Every set of 1 .. max_failed CubeSats once (ids from 1), and a lost stage per
    # CubeSat when asked for.
    count = len(cd.load_problem(problem_file).cubesats)
    expected = sorted(
        list(s)
        for k in range(1, keywords["max_failed"] + 1)
        for s in itertools.combinations(range(1, count + 1), k)
    )
    cases = result.summary.cases
    assert sorted(list(c.failed) for c in cases if c.failed) == expected
    assert len([c for c in cases if c.failed_stage]) == (count if stages else 0)

    saved = result.save(tmp_path / "saved")
    assert _files(saved) == _files(folder)
    written = json.loads((saved / "summary.json").read_text())
    assert written["out_dir"] == str(saved.absolute())
    assert _comparable(written) == _comparable(printed)
    assert (saved / "cases.csv").read_text() == (folder / "cases.csv").read_text()

    figures = result.plot()
    try:
        assert set(figures) == {p.removesuffix(".png") for p in _files(saved) if p.endswith(".png")}
        assert set(figures) == {"authority_loss"}
    finally:
        for figure in figures.values():
            plt.close(figure)
