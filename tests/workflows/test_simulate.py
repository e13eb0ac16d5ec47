"""``casadi_debris.simulate`` is the ``simulate`` command: one call from Python gives the
run the command writes, with the same figures."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main
from casadi_debris.errors import InputShapeError, OutputError


@pytest.fixture(scope="module")
def short_run() -> cd.SimulationResult:
    """The paper's slew cut to its first 60 s, flown from Python by its shipped name (an
    immutable result, shared by the tests that only read it)."""
    return cd.simulate("paper_slew", duration_s=60.0)


def test_python_and_command_line_give_the_same_run(short_run: cd.SimulationResult) -> None:
    result = CliRunner().invoke(
        main, ["simulate", "paper_slew", "--duration-s", "60", "--json"], catch_exceptions=False
    )
    assert result.exit_code == 0
    from_cli = json.loads(result.stdout)
    from_python = short_run.summary.to_json()
    for volatile in ("wall_time_s",):
        from_cli.pop(volatile), from_python.pop(volatile)
    assert from_cli == from_python


def test_the_result_holds_the_arrays_the_summary_reads(short_run: cd.SimulationResult) -> None:
    import numpy as np

    run = short_run.result
    assert run.time_s[-1] == pytest.approx(60.0)
    largest_deg = float(np.degrees(np.abs(run.error_rad).max()))
    assert short_run.summary.run.max_error_deg == pytest.approx(largest_deg, rel=1e-12)
    assert short_run.summary.requirements_met is True
    assert short_run.problem.simulation.duration_s == pytest.approx(60.0)


def test_save_writes_the_commands_folder_and_never_overwrites(
    short_run: cd.SimulationResult, tmp_path: Path
) -> None:
    out = short_run.save(tmp_path / "run", plots=False)
    written = json.loads((out / "summary.json").read_text())
    assert written["out_dir"] == str(out.absolute())
    assert written["max_error_deg"] == short_run.summary.run.max_error_deg
    assert (out / "series.csv").is_file() and not (out / "closed_loop.png").exists()
    with pytest.raises(OutputError):
        short_run.save(out, plots=False)
    short_run.save(out, plots=False, overwrite=True)


def test_failed_cubesats_are_one_based_and_checked() -> None:
    with pytest.raises(InputShapeError, match="from 1 to 24"):
        cd.simulate("paper_slew", duration_s=10.0, failed=[0])
    run = cd.simulate("paper_slew", duration_s=10.0, failed=[1, 24])
    failed = run.result.propulsion.failed_cubesats
    assert failed[0] and failed[23] and failed.sum() == 2


def test_plot_returns_the_figures_save_writes_and_writes_nothing(
    short_run: cd.SimulationResult, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import matplotlib.pyplot as plt
    import numpy as np

    monkeypatch.chdir(tmp_path)
    figures = short_run.plot()
    assert set(figures) == {"closed_loop", "thrust"}
    assert list(tmp_path.iterdir()) == []
    error_axes = figures["closed_loop"].axes[1]
    drawn = error_axes.lines[0].get_ydata()
    # A slew is drawn in degrees: the first error line is the x error of the run.
    np.testing.assert_allclose(drawn, np.degrees(short_run.result.error_rad[:, 0]))
    for figure in figures.values():
        plt.close(figure)


def test_a_slew_turned_by_keyword_is_titled_by_what_flew() -> None:
    import matplotlib.pyplot as plt

    run = cd.simulate("paper_slew", duration_s=20.0, angle_deg=5.0)
    assert run.problem.simulation.slew is not None
    assert run.problem.simulation.slew.angle_deg == 5.0
    figures = run.plot()
    title = figures["closed_loop"].axes[0].get_title()
    assert "5 deg" in title and "180" not in title
    for figure in figures.values():
        plt.close(figure)


def test_the_shipped_controller_flies_another_plant_only_when_asked(
    caplog: pytest.LogCaptureFixture,
) -> None:
    from casadi_debris.errors import ControllerMismatchError

    with pytest.raises(ControllerMismatchError, match="--allow-mismatch"):
        cd.simulate("side_engines_12", duration_s=5.0)
    run = cd.simulate("side_engines_12", duration_s=5.0, allow_mismatch=True)
    assert run.summary.problem == "side_engines_12"
    assert "designed for another plant" in caplog.text


def test_the_summary_reads_in_python_as_its_json(short_run: cd.SimulationResult) -> None:
    """``summary.json`` flattens the run's figures into the record; Python reads them the
    same way (``run.summary.max_error_deg``), each equal to the nested value."""
    summary = short_run.summary
    flat = summary.to_json()
    for name in ("max_error_deg", "fuel_kg", "final_error_arcsec", "settle_band_arcsec"):
        assert getattr(summary, name) == getattr(summary.run, name) == flat[name]
    with pytest.raises(AttributeError):
        _ = summary.no_such_figure
