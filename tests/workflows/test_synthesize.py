"""``casadi_debris.synthesize`` is the ``synthesize`` command: the same design from Python
as ``casadi-debris synthesize ... --json`` prints and writes (quick settings: the H-inf
step only, a coarse grid), its controller stabilising the plant it was designed for."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main
from casadi_debris.dynamics import build_model, linearize
from casadi_debris.errors import OutputError
from casadi_debris.workflows import load_controller

QUICK = {"mu_points": 10, "max_iterations": 0, "samples": 20}
QUICK_OPTIONS = ["--mu-points", "10", "--max-iterations", "0", "--samples", "20"]
VOLATILE = ("time_s", "controller_path")


def _without_volatile(payload: dict) -> dict:
    return {k: v for k, v in payload.items() if k not in VOLATILE}


@pytest.mark.parametrize("problem", [None, pytest.param("rigid_no_arrays", marks=pytest.mark.slow)])
def test_python_and_command_line_give_the_same_design_and_folder(
    problem: str | None, tmp_path: Path
) -> None:
    design = cd.synthesize(problem, **QUICK)
    out = tmp_path / "cli"
    arguments = [*([problem] if problem else []), *QUICK_OPTIONS, "--out", str(out)]
    result = CliRunner().invoke(main, ["synthesize", *arguments, "--json"], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    from_cli = json.loads(result.stdout)
    assert from_cli["controller_path"] == str((out / "controller.json").absolute())
    assert design.summary.controller_path is None
    assert _without_volatile(design.summary.to_json()) == _without_volatile(from_cli)
    saved = design.save(tmp_path / "python")
    assert sorted(p.name for p in saved.iterdir()) == sorted(p.name for p in out.iterdir())
    written = json.loads((saved / "summary.json").read_text())
    assert written["controller_path"] == str((saved / "controller.json").absolute())
    record, _ = load_controller(saved / "controller.json")
    np.testing.assert_array_equal(record.reduced.A, design.record.reduced.A)
    assert record.problem_sha256 == design.problem.plant_sha256
    with pytest.raises(OutputError):
        design.save(saved)
    assert design.plot() == {}  # the command draws nothing


def test_the_controller_stabilises_its_design_plant() -> None:
    import control

    design = cd.synthesize("rigid_no_arrays", **QUICK)
    record = design.record
    assert design.summary.order_reduced == record.reduced.nstates
    modes = record.details.get("design_plant_modes", "first")
    plant = linearize(build_model(design.problem, modes=modes), sensor=True, units="deg_mNm")
    # Negative feedback of the attitude error through u = K e, closed by python-control.
    closed = control.feedback(plant * record.reduced, np.eye(3))
    assert np.max(np.real(closed.poles())) < 0.0
