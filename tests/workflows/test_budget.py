"""``casadi_debris.budget`` is the ``budget`` command: the budgets ``casadi-debris budget
--json`` prints, from Python, checked against the rocket equation written out."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main
from casadi_debris.errors import OutputError


def _cli_json(*arguments: str) -> dict:
    result = CliRunner().invoke(main, ["budget", *arguments, "--json"], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


@pytest.mark.parametrize("problem", [None, "side_engines_12"])
def test_python_and_command_line_give_the_same_budgets(problem: str | None) -> None:
    budgets = cd.budget(problem)
    assert budgets.summary.to_json() == _cli_json(*([problem] if problem else []))
    assert [item.key for item in budgets.items] == list(budgets.summary.figures)


def test_a_lone_cubesats_dv_is_the_rocket_equation() -> None:
    budgets = cd.budget()
    problem = budgets.problem
    engine, cubesat = problem.cubesats[0].engines[0], problem.cubesats[0]
    g0 = problem.constants.standard_gravity_m_s2
    propellant_kg = engine.thrust_per_stage_mN * 1e-3 * engine.stage_life_h * 3600.0
    propellant_kg /= engine.isp_s * g0
    dv = engine.isp_s * g0 * math.log(cubesat.mass_kg / (cubesat.mass_kg - propellant_kg))
    figures = budgets.summary.figures
    assert figures["stage_propellant_kg"] == pytest.approx(propellant_kg, rel=1e-12)
    assert figures["dv_cubesat_one_stage_m_s"] == pytest.approx(dv, rel=1e-12)


def test_save_writes_the_summary_and_never_overwrites(tmp_path: Path) -> None:
    budgets = cd.budget()
    out = budgets.save(tmp_path / "budget")
    assert json.loads((out / "summary.json").read_text()) == budgets.summary.to_json()
    with pytest.raises(OutputError):
        budgets.save(out)
    assert budgets.plot() == {}  # the command draws nothing
