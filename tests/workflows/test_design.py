"""The design workflow: what a design is verified on, and its command's bad input."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.cli import main
from casadi_debris.config import default_problem_path
from casadi_debris.report import DesignSummary
from casadi_debris.workflows import QUICK, load_controller
from casadi_debris.workflows._design import SLEW_RUN_FACTOR, _classical, verification_problems

PROBLEMS = default_problem_path().parent


def test_a_hold_problem_is_verified_on_a_slew_about_its_slowest_axis(problem, geometry):
    slew_problem, pointing_problem = verification_problems(problem)
    slew = slew_problem.simulation.slew
    assert slew is not None and slew.angle_deg == 180.0 and slew.method == "bang-bang"
    # by hand: the share of the authority the disturbance leaves, over the inertia
    authority = np.array([4.608, 2.016, 4.32])  # mNm, zero net force (model --json)
    fraction = (2 / 3) * (1 - 0.7 / authority)
    acceleration = fraction * authority * 1e-3 / np.diag(geometry.inertia_total_kgm2)
    assert slew.axis == "xyz"[int(np.argmin(acceleration))] == "y"
    assert math.isclose(slew.torque_fraction, fraction[1], rel_tol=1e-3)
    bang_bang_s = 2 * math.sqrt(math.pi / acceleration[1])
    assert math.isclose(
        slew_problem.simulation.duration_s, SLEW_RUN_FACTOR * bang_bang_s, rel_tol=1e-3
    )
    assert pointing_problem.simulation.reference == "hold"
    assert pointing_problem.simulation.duration_s == problem.disturbance.period_min * 60
    assert slew_problem.plant_sha256 == pointing_problem.plant_sha256 == problem.plant_sha256


def test_a_slew_problem_keeps_its_own_slew_and_failures_are_left_out():
    paper_slew = load_problem(PROBLEMS / "paper_slew.toml")
    slew_problem, pointing_problem = verification_problems(paper_slew, QUICK)
    assert slew_problem.simulation.slew == paper_slew.simulation.slew
    assert slew_problem.simulation.duration_s == paper_slew.simulation.duration_s
    assert pointing_problem.simulation.duration_s == paper_slew.disturbance.period_min * 60
    assert slew_problem.simulation.failures == ()


def test_design_refuses_a_disturbance_the_swarm_cannot_overcome(tmp_path: Path):
    problem_file = tmp_path / "weak.toml"
    problem_file.write_text(
        f'extends = "{(PROBLEMS / "paper.toml").as_posix()}"\nname = "weak"\n'
        "[disturbance]\namplitude_mNm = [0.7, 3.0, 0.7]\nperiod_min = 98.5\n"
        "phase_deg = [0.0, 0.0, 0.0]\n"
    )
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["design", str(problem_file), "--out", str(out)])
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert (
        len(lines) == 1 and "disturbance.amplitude_mNm" in lines[0] and "y (2.02 mNm)" in lines[0]
    )
    assert not out.exists()


def test_design_refuses_an_existing_folder_it_did_not_write(tmp_path: Path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    result = CliRunner().invoke(main, ["design", "--out", str(out)])
    assert result.exit_code == 2
    assert (out / "notes.txt").read_text() == "keep me"


def test_a_classical_controller_file_loads_as_it_was_designed(problem, tmp_path: Path):
    """A PD, PID or LQG record goes through the controller file and back unchanged, bound
    to its plant, with its settings and no μ."""
    for method, states in (("pd", 3), ("pid", 6), ("lqr", 6)):
        record = _classical(problem, method)
        path = tmp_path / f"{method}.json"
        path.write_text(json.dumps(record.to_dict()))
        loaded, _ = load_controller(path)
        assert loaded.reduced.nstates == states and loaded.mu_peak is None
        assert loaded.problem_sha256 == problem.plant_sha256
        assert loaded.details["method"] == method
        np.testing.assert_allclose(loaded.reduced.A, record.reduced.A)
        np.testing.assert_allclose(loaded.reduced.D, record.reduced.D)


@pytest.mark.slow
def test_design_with_a_pid_is_verified_like_the_mu_design(tmp_path: Path):
    out = tmp_path / "pid"
    result = CliRunner().invoke(
        main,
        [
            "-q",
            "design",
            "--method",
            "pid",
            "--quick",
            "--workers",
            "1",
            "--out",
            str(out),
            "--json",
        ],
    )
    assert result.exit_code == 0, result.output
    summary = json.loads(result.output)
    assert summary["method"] == "pid" and summary["mu_peak"] is None and summary["attempts"] == []
    keys = [row["key"] for row in summary["rows"]]
    assert keys[:4] == [
        "pointing_arcsec",
        "slew_max_error_deg",
        "margins_sampled",
        "unstable_samples",
    ]
    slew = json.loads((out / "slew" / "summary.json").read_text())
    assert summary["rows"][1]["values"][1] == slew["worst"]["max_error_deg"]["value"]
    assert "PID controller for paper" in (out / "report.md").read_text()
    # One JSON form: on stdout and on disk, read back into the record it came from.
    assert json.loads((out / "summary.json").read_text()) == summary
    assert DesignSummary.from_json(summary).to_json() == summary
    assert set(summary["scalings"]) == {
        "error_scaling_deg", "control_scaling_mNm", "disturbance_scaling_mNm", "ve_ratio",
        "disturbance_frequency_rad_s", "pointing_per_mu_arcsec", "reference_scaling_deg",
    }  # fmt: skip
    assert summary["body"]["bandwidth_from"] == "paper"
    assert summary["requirements_met"] is (
        summary["requirements_passed"] == summary["requirements"]
    )


def test_each_missed_requirement_gets_its_binding_limit_from_the_runs(problem):
    """The wiring from the requirement rows and the campaigns to the limits: the worst of
    nominal and corner, the slew's own torque fraction, nothing for a requirement met."""
    from types import SimpleNamespace

    from casadi_debris.report import RequirementRow, WorstValueSummary
    from casadi_debris.workflows import binding_limits

    slew_problem, _ = verification_problems(problem, QUICK)
    pointing = SimpleNamespace(
        nominal={"max_error_arcsec": 70.0},
        worst={"max_error_arcsec": WorstValueSummary(81.0, "corner-0002")},
    )
    slew = SimpleNamespace(
        nominal={"max_error_deg": 0.5},
        worst={
            "max_error_deg": WorstValueSummary(0.9, "corner-0001"),
            "torque_saturated_s": WorstValueSummary(30.0, "corner-0001"),
        },
    )
    rows = [
        RequirementRow("pointing_arcsec", "", "", "", (70.0, 81.0), False),
        RequirementRow("slew_max_error_deg", "", "", "", (0.5, 0.9), False),
        RequirementRow("margins_sampled", "", "", "", (13.0, 45.0), True),
    ]
    campaigns = {"pointing": pointing, "slew": slew}
    limits = binding_limits(problem, rows, campaigns, None, slew_problem)  # type: ignore[arg-type]
    assert [b.requirement for b in limits] == ["pointing_arcsec", "slew_max_error_deg"]
    assert limits[0].figures["worst_arcsec"] == 81.0 and limits[0].figures["axis"] == "y"
    fraction = slew_problem.simulation.slew.torque_fraction
    assert limits[1].figures["torque_fraction"] == fraction
    assert f"torque fraction {fraction * 0.6 / 0.9:.3g}" in limits[1].remedies[0]
    met = [dataclasses.replace(row, met=True) for row in rows]
    assert binding_limits(problem, met, campaigns, None, slew_problem) == ()  # type: ignore[arg-type]


def test_cd_design_refuses_a_folder_it_did_not_write_before_any_work(tmp_path: Path):
    import casadi_debris as cd
    from casadi_debris.errors import OutputError

    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    with pytest.raises(OutputError):
        cd.design(out=out, quick=True, progress=lambda stage: pytest.fail(f"ran {stage}"))
    assert (out / "notes.txt").read_text() == "keep me"


@pytest.mark.slow
def test_cd_design_is_the_design_command(tmp_path: Path):
    """The same classical design from Python as from the command line: summary, folder,
    controller; ``save`` copies the folder and ``plot`` gives the margin figures."""
    import matplotlib.pyplot as plt

    import casadi_debris as cd
    from casadi_debris.store import MARKER_NAME

    def files(folder: Path) -> list[str]:
        found = folder.rglob("*")
        return sorted(
            str(p.relative_to(folder)) for p in found if p.is_file() and p.name != MARKER_NAME
        )

    designed = cd.design(method="pd", quick=True, workers=1, out=tmp_path / "python")
    out = tmp_path / "cli"
    arguments = ["--method", "pd", "--quick", "--workers", "1", "--out", str(out), "--json"]
    result = CliRunner().invoke(main, ["-q", "design", *arguments], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    volatile = ("time_s", "out_dir", "controller_path")
    from_cli = {k: v for k, v in json.loads(result.stdout).items() if k not in volatile}
    from_python = {k: v for k, v in designed.summary.to_json().items() if k not in volatile}
    assert from_python == from_cli
    assert files(designed.folder) == files(out)
    loaded, _ = load_controller(designed.folder / "controller.json")
    np.testing.assert_array_equal(loaded.reduced.A, designed.record.reduced.A)
    assert designed.margins.summary == dataclasses.replace(
        designed.margins.summary, out_dir=str((designed.folder / "margins").absolute())
    )
    assert files(designed.save(tmp_path / "copy")) == files(out)
    figures = designed.plot()
    assert "margins/margins" in figures
    assert {f"{name}.png" for name in figures} <= set(files(out))
    for figure in figures.values():
        plt.close(figure)
