"""``casadi_debris.reproduce`` is the ``reproduce`` command: the same report from Python
as ``casadi-debris reproduce`` writes and prints."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main
from casadi_debris.errors import OutputError
from workflow_files import files_written as _files

VOLATILE = ("time_s", "out_dir")


def test_a_folder_it_did_not_write_is_refused_before_any_work(tmp_path: Path) -> None:
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    with pytest.raises(OutputError):
        cd.reproduce(out, quick=True, progress=lambda stage: pytest.fail(f"ran {stage}"))
    assert (out / "notes.txt").read_text() == "keep me"


@pytest.mark.slow
def test_python_and_command_line_write_the_same_report(tmp_path: Path) -> None:
    import matplotlib.pyplot as plt

    stages: list[str] = []
    paper = cd.reproduce(tmp_path / "python", quick=True, workers=1, progress=stages.append)
    assert stages[0] == "model and budgets" and len(stages) == 4
    out = tmp_path / "cli"
    result = CliRunner().invoke(
        main,
        ["reproduce", "--quick", "--workers", "1", "--out", str(out), "--json"],
        catch_exceptions=False,
    )
    assert result.exit_code == 0, result.output
    from_cli = {k: v for k, v in json.loads(result.stdout).items() if k not in VOLATILE}
    from_python = {k: v for k, v in paper.summary.to_json().items() if k not in VOLATILE}
    assert from_python == from_cli
    assert paper.summary.out_dir == str((tmp_path / "python").absolute())
    assert _files(paper.folder) == _files(out)
    copied = paper.save(tmp_path / "copy")
    assert _files(copied) == _files(out)
    assert json.loads((copied / "report.md").with_name("summary.json").read_text())["rows"] == (
        paper.summary.rows
    )
    figures = paper.plot()
    assert set(figures) == {"margins/mu", "margins/uncertainty_weight", "margins/loop_shapes",
                            "margins/margins"}  # fmt: skip
    assert {f"{name}.png" for name in figures} <= set(_files(out))
    for figure in figures.values():
        plt.close(figure)
