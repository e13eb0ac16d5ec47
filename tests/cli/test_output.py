"""Every command that writes: an existing folder or file is never deleted without --overwrite."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.store import MARKER_NAME

FAST_WRITERS = [
    ["slew", "--method", "bang-bang"],
    ["simulate", "--duration-s", "1"],
    ["montecarlo", "--max-cases", "1", "--workers", "1"],
    ["margins", "--samples", "1", "--no-plots"],
    ["compare", "PAPER"],
    ["reproduce", "--quick"],
]


@pytest.fixture()
def in_tmp(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _args(command: list[str]) -> list[str]:
    from casadi_debris.config import default_problem_path

    return [str(default_problem_path()) if a == "PAPER" else a for a in command]


@pytest.mark.parametrize("command", FAST_WRITERS, ids=lambda c: c[0])
@pytest.mark.parametrize("where", ["folder", "dot"])
def test_an_existing_folder_is_refused_before_any_work(in_tmp: Path, command, where) -> None:
    folder = in_tmp / "mine"
    folder.mkdir()
    (folder / "sentinel.txt").write_text("keep me")
    out = "mine" if where == "folder" else "."
    if where == "dot":
        (in_tmp / "sentinel.txt").write_text("keep me too")
    result = CliRunner().invoke(main, [*_args(command), "--out", out])
    assert result.exit_code == 2, result.output
    assert "--out" in result.output and "--overwrite" in result.output
    assert len(result.output.strip().splitlines()) == 1, result.output
    assert (folder / "sentinel.txt").read_text() == "keep me"
    expected = {"mine", "sentinel.txt"} if where == "dot" else {"mine"}
    assert {p.name for p in in_tmp.iterdir()} == expected


@pytest.mark.parametrize("command", FAST_WRITERS, ids=lambda c: c[0])
def test_overwrite_never_replaces_a_folder_the_toolkit_did_not_write(in_tmp: Path, command) -> None:
    folder = in_tmp / "mine"
    folder.mkdir()
    (folder / "sentinel.txt").write_text("keep me")
    result = CliRunner().invoke(main, [*_args(command), "--out", "mine", "--overwrite"])
    assert result.exit_code == 2, result.output
    assert "not written by casadi-debris" in result.output
    assert (folder / "sentinel.txt").read_text() == "keep me"


def test_slew_overwrite_replaces_its_own_result_and_nothing_else(in_tmp: Path) -> None:
    runner = CliRunner()
    first = runner.invoke(main, ["slew", "--method", "bang-bang", "--out", "run", "--json"])
    assert first.exit_code == 0, first.output
    assert (in_tmp / "run" / MARKER_NAME).is_file()
    again = runner.invoke(main, ["slew", "--method", "bang-bang", "--out", "run"])
    assert again.exit_code == 2 and "--overwrite" in again.output
    replaced = runner.invoke(
        main, ["slew", "--method", "bang-bang", "--angle-deg", "90", "--out", "run", "--overwrite"]
    )
    assert replaced.exit_code == 0, replaced.output
    summary = json.loads((in_tmp / "run" / "summary.json").read_text())
    assert summary["angle_deg"] == pytest.approx(90.0)
    assert {p.name for p in in_tmp.iterdir()} == {"run"}


def test_synthesize_writes_a_run_folder_never_over_the_users(in_tmp: Path) -> None:
    (in_tmp / "mine").mkdir()
    (in_tmp / "mine" / "controller.json").write_text('{"mine": true}')
    result = CliRunner().invoke(main, ["synthesize", "--out", "mine", "--max-iterations", "0"])
    assert result.exit_code == 2, result.output
    assert "--out" in result.output and "--overwrite" in result.output
    assert (in_tmp / "mine" / "controller.json").read_text() == '{"mine": true}'
    # A file name, as --out once took: refused naming the folder it would mean.
    result = CliRunner().invoke(main, ["synthesize", "--out", "k.json"])
    assert result.exit_code == 2 and "k/controller.json" in result.output
    assert sorted(p.name for p in in_tmp.iterdir()) == ["mine"]


def test_an_output_below_a_file_is_refused_before_work(in_tmp: Path) -> None:
    (in_tmp / "afile").write_text("x")
    result = CliRunner().invoke(main, ["slew", "--method", "bang-bang", "--out", "afile/run"])
    assert result.exit_code == 2, result.output
    assert "afile is a file" in result.output
