"""``casadi_debris.model`` is the ``model`` command: the description ``casadi-debris model
--json`` prints, from Python, with the model it describes."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main
from casadi_debris.dynamics import Model
from casadi_debris.errors import OutputError


def _cli_json(*arguments: str) -> dict:
    result = CliRunner().invoke(main, ["model", *arguments, "--json"], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


def test_cd_model_is_the_job_not_a_package() -> None:
    assert callable(cd.model) and cd.model.__module__ == "casadi_debris.workflows._model"
    assert "model" in cd.__all__


@pytest.mark.parametrize("problem", [None, "side_engines_12", "rigid_no_arrays"])
def test_python_and_command_line_describe_the_same_system(problem: str | None) -> None:
    described = cd.model(problem)
    assert described.summary.to_json() == _cli_json(*([problem] if problem else []))


def test_the_description_adds_up_the_problems_bodies() -> None:
    described = cd.model("side_engines_12")
    problem = described.problem
    # Masses and engine counts straight from the problem file's bodies.
    mass = problem.hub.mass_kg + sum(a.mass_kg for a in problem.arrays)
    mass += sum(c.mass_kg for c in problem.cubesats)
    assert described.summary.mass_kg == pytest.approx(mass, rel=1e-12)
    engines = sum(len(c.engines) for c in problem.cubesats)
    assert len(described.summary.thrusters) == engines
    assert [t.engine for t in described.summary.thrusters] == list(range(1, engines + 1))
    # The model returned is the one described, and knows its problem.
    assert isinstance(described.model, Model) and described.model.problem is problem
    np.testing.assert_allclose(
        described.summary.inertia_total_kgm2, described.model.geometry.inertia_total_kgm2, atol=1e-6
    )


def test_save_writes_the_summary_and_never_overwrites(tmp_path: Path) -> None:
    described = cd.model()
    out = described.save(tmp_path / "model")
    assert json.loads((out / "summary.json").read_text()) == described.summary.to_json()
    with pytest.raises(OutputError):
        described.save(out)
    assert described.plot() == {}  # the command draws nothing
