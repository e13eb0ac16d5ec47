"""A misspelt shipped problem name gets "did you mean", on the CLI and from Python."""

from __future__ import annotations

import re

import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.cli import main
from casadi_debris.config import shipped_problems
from casadi_debris.errors import ProblemFileError


def _edit_distance(a: str, b: str) -> int:
    """Levenshtein distance, by the textbook recurrence (not difflib's ratio)."""
    row = list(range(len(b) + 1))
    for i, char_a in enumerate(a, 1):
        previous, row[0] = row[0], i
        for j, char_b in enumerate(b, 1):
            previous, row[j] = (
                row[j],
                min(row[j] + 1, row[j - 1] + 1, previous + (char_a != char_b)),
            )
    return row[-1]


def _typos() -> list[tuple[str, str]]:
    """Each shipped name with one letter dropped from its middle (and one swapped)."""
    typos = []
    for name in shipped_problems():
        middle = len(name) // 2
        typos.append((name, name[:middle] + name[middle + 1 :]))
        typos.append(
            (name, name[: middle - 1] + name[middle] + name[middle - 1] + name[middle + 1 :])
        )
    return [(name, typo) for name, typo in typos if typo != name]  # "pp" swapped is no typo


@pytest.mark.parametrize(("name", "typo"), _typos())
def test_a_misspelt_shipped_name_is_answered_with_the_closest_one(
    tmp_path, monkeypatch, name: str, typo: str
) -> None:
    monkeypatch.chdir(tmp_path)  # no file of that name where the command runs
    result = CliRunner().invoke(main, ["model", typo])
    assert result.exit_code == 2 and result.output.count("\n") == 1, result.output
    suggested = re.search(r"did you mean (\w+)\?", result.output)
    assert suggested is not None, result.output
    distances = {other: _edit_distance(typo, other) for other in shipped_problems()}
    # The suggestion is a shipped name, and none is closer to what was typed.
    assert distances[suggested.group(1)] == min(distances.values()) <= distances[name]


def test_a_name_like_none_gets_the_list_not_a_guess(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, ["model", "qqqq"])
    assert result.exit_code == 2 and "did you mean" not in result.output
    assert "casadi-debris problems lists them" in result.output


def test_python_and_extends_get_the_suggestion_too(tmp_path) -> None:
    with pytest.raises(ProblemFileError, match=r"did you mean paper_slew\?"):
        load_problem(tmp_path / "papr_slew")
    child = tmp_path / "child.toml"
    child.write_text('extends = "paper_pointng"\n')
    with pytest.raises(ProblemFileError, match=r"extends.*did you mean paper_pointing\?"):
        load_problem(child)
