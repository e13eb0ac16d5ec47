"""compare: fuel over the same window, verdicts against the requirements, failures in their row."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import matplotlib.pyplot as plt
import pytest
from click.testing import CliRunner

from casadi_debris import load_problem
from casadi_debris.allocation import Allocator
from casadi_debris.cli import main
from casadi_debris.config import FailureEvent, with_duration
from casadi_debris.dynamics import build_model
from casadi_debris.errors import ProblemFileError
from casadi_debris.guidance import scenario_reference
from casadi_debris.simulation import simulate_closed_loop
from casadi_debris.store import MARKER_NAME
from casadi_debris.workflows import compare, controller_for
from workflow_files import short_problem as _short

SHORT_S, LONG_S = 60.0, 90.0


def _every_cubesat_lost(problem):
    """Every CubeSat failed 10 s into the run: nothing can fire, the run gives up."""
    lost = tuple(FailureEvent(10.0, cubesat, None) for cubesat in range(24))
    simulation = dataclasses.replace(problem.simulation, failures=lost)
    return dataclasses.replace(problem, name="all_lost", simulation=simulation)


@pytest.fixture(scope="module")
def comparison(tmp_path_factory: pytest.TempPathFactory):
    slew = load_problem("paper_slew")
    variants = [
        with_duration(slew, LONG_S),
        dataclasses.replace(with_duration(load_problem("paper_pointing"), SHORT_S), name="hold"),
        _every_cubesat_lost(with_duration(slew, SHORT_S)),
    ]
    out = tmp_path_factory.mktemp("compare") / "out"
    result = compare(variants)
    result.save(out)
    return result.summary, variants, out


def test_fuel_over_the_common_window_is_what_a_run_of_that_length_burns(comparison) -> None:
    summary, variants, _ = comparison
    assert summary.window_s == SHORT_S
    long = summary.variants[0]
    assert long.duration_s == pytest.approx(LONG_S) and long.fuel_kg > long.fuel_window_kg > 0
    # Independently: the same problem flown for the window's length alone.
    problem = with_duration(variants[0], SHORT_S)
    record, _ = controller_for(problem, None)
    model = build_model(problem)
    alone = simulate_closed_loop(
        model,
        record.reduced,
        scenario_reference(problem),
        allocator=Allocator.from_problem(problem, model.geometry),
    )
    assert long.fuel_window_kg == pytest.approx(alone.summary().fuel_kg, rel=1e-9)


def test_each_run_is_judged_against_its_own_requirement(comparison) -> None:
    summary, variants, _ = comparison
    slew, hold = summary.variants[:2]
    assert (slew.requirement, slew.required) == (
        "slew_error_deg",
        variants[0].requirements.slew_error_deg,
    )
    assert slew.requirement_met == (slew.max_error_deg <= slew.required)
    assert hold.requirement == "pointing_arcsec" and hold.fuel_slew_kg is None
    assert hold.requirement_met == (
        hold.max_error_arcsec <= variants[1].requirements.pointing_arcsec
    )


def test_a_failing_variant_is_reported_in_its_row_and_the_others_stay(comparison) -> None:
    summary, _, out = comparison
    failed = summary.variants[2]
    assert failed.variant == "all_lost" and failed.error and failed.fuel_kg is None
    assert failed.requirement_met is None
    written = json.loads((out / "summary.json").read_text())
    assert [row["variant"] for row in written["variants"]] == ["paper_slew", "hold", "all_lost"]
    assert "run failed" in (out / "comparison.md").read_text()
    assert (out / "comparison.png").exists() and (out / "comparison.csv").exists()


def test_a_slew_the_body_cannot_do_is_refused_before_any_variant_flies(tmp_path: Path) -> None:
    slew = with_duration(load_problem("paper_slew"), SHORT_S)
    too_fast = dataclasses.replace(slew.simulation.slew, duration_s=100.0, torque_fraction=None)
    bad = dataclasses.replace(slew, simulation=dataclasses.replace(slew.simulation, slew=too_fast))
    with pytest.raises(ProblemFileError, match=r"simulation\.slew\.duration_s"):
        compare([slew, bad])
    assert not (tmp_path / "out").exists()


def _files(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name != MARKER_NAME)


def test_python_and_the_command_line_compare_alike(tmp_path: Path) -> None:
    """The paper's slew beside a debris of another shape (one array) holding its attitude,
    flown by the paper's controller anyway."""
    files = [_short(tmp_path, "paper_slew", 40.0), _short(tmp_path, "gallery/one_array", 30.0)]
    labels: list[str] = []
    result = compare(files, allow_mismatch=True, progress=labels.append)
    assert labels == ["short_paper_slew", "short_one_array"]
    assert result.summary.out_dir is None
    assert result.summary.window_s == 30.0

    folder = tmp_path / "cli"
    args = [*map(str, files), "--allow-mismatch", "--out", str(folder), "--json"]
    command = CliRunner().invoke(main, ["compare", *args], catch_exceptions=False)
    assert command.exit_code == 0, command.output
    printed = json.loads(command.stdout)
    ours = json.loads(json.dumps(result.summary.to_json()))
    assert {**ours, "out_dir": None} == {**printed, "out_dir": None}

    saved = result.save(tmp_path / "saved")
    assert _files(saved) == _files(folder)
    written = json.loads((saved / "summary.json").read_text())
    assert written == {**printed, "out_dir": str(saved.absolute())}
    assert (saved / "comparison.csv").read_text() == (folder / "comparison.csv").read_text()

    figures = result.plot()
    try:
        assert set(figures) == {"comparison"} and len(figures["comparison"].axes) == 5
    finally:
        for figure in figures.values():
            plt.close(figure)
