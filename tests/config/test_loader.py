"""Shipped problems by name: from any folder, in extends, and never over a file of the user's."""

from __future__ import annotations

import json
import os
import tomllib
from pathlib import Path

import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.cli import main
from casadi_debris.config import default_problem_path, problem_path, shipped_problems
from casadi_debris.errors import ProblemFileError

PACKAGE_PROBLEMS = Path(__file__).parents[2] / "src" / "casadi_debris" / "problems"


@pytest.fixture
def elsewhere(tmp_path: Path):
    """Run from a folder outside the repository."""
    before = Path.cwd()
    os.chdir(tmp_path)
    yield tmp_path
    os.chdir(before)


def test_every_shipped_file_has_a_name_and_nothing_else_does() -> None:
    on_disk = {p.stem: p.resolve() for p in PACKAGE_PROBLEMS.rglob("*.toml")}
    assert {k: v.resolve() for k, v in shipped_problems().items()} == on_disk
    assert {"paper", "paper_slew", "paper_pointing", "one_array"} <= set(on_disk)


@pytest.mark.parametrize("name", ["paper_slew", "paper_slew.toml"])
def test_a_shipped_name_loads_from_any_folder(elsewhere: Path, name: str) -> None:
    problem = load_problem(name)
    assert problem.name == "paper_slew"
    assert Path(problem.source) == (PACKAGE_PROBLEMS / "paper_slew.toml").resolve()


def test_extends_names_a_shipped_problem_from_any_folder(elsewhere: Path) -> None:
    (elsewhere / "mine.toml").write_text('extends = "paper_slew"\nname = "mine"\n')
    mine = load_problem("mine.toml")
    shipped = load_problem("paper_slew")
    assert mine.name == "mine" and mine.plant_sha256 == shipped.plant_sha256
    assert repr(mine.simulation) == repr(shipped.simulation)


def test_a_file_of_the_users_wins_over_a_shipped_name(elsewhere: Path) -> None:
    text = (PACKAGE_PROBLEMS / "paper.toml").read_text().replace('name = "paper"', 'name = "own"')
    assert tomllib.loads(text)["name"] == "own"
    (elsewhere / "paper_slew.toml").write_text(text)
    assert load_problem("paper_slew.toml").name == "own"
    assert problem_path("paper_slew.toml") == Path("paper_slew.toml")
    (elsewhere / "child.toml").write_text('extends = "paper_slew.toml"\nname = "child"\n')
    child = load_problem("child.toml").simulation
    assert (
        repr(child)
        == repr(load_problem("paper").simulation)
        != repr(load_problem("paper_slew").simulation)
    )


def test_an_unknown_name_says_where_the_shipped_ones_are(elsewhere: Path) -> None:
    with pytest.raises(ProblemFileError, match=r"no such problem file.*casadi-debris problems"):
        load_problem("paper_slw")
    assert problem_path("sub/paper") == Path("sub/paper")  # a path is never a name


def test_problems_lists_every_shipped_problem_and_each_loads() -> None:
    result = CliRunner().invoke(main, ["problems", "--json"])
    assert result.exit_code == 0, result.output
    rows = json.loads(result.output)["problems"]
    assert [row["name"] for row in rows] == list(shipped_problems())
    for row in rows:
        assert load_problem(row["name"]).description == row["description"]


def test_the_papers_problems_are_listed_before_the_gallery() -> None:
    root = default_problem_path().parent
    depths = [len(path.relative_to(root).parts) for path in shipped_problems().values()]
    assert depths == sorted(depths) and next(iter(shipped_problems())) == "paper"
