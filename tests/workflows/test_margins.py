"""``casadi_debris.margins`` is the ``margins`` command: the same study from Python as
``casadi-debris margins ... --json`` prints and writes, its phase margins checked against
the loops closed by hand."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from scipy.optimize import brentq

import casadi_debris as cd
from casadi_debris.cli import main
from casadi_debris.dynamics import build_model, linearize
from casadi_debris.errors import ControllerMismatchError

SAMPLES = 70  # the 64 corners and a few random plants: seconds
VOLATILE = ("time_s", "out_dir")


def _without_volatile(payload: dict) -> dict:
    return {k: v for k, v in payload.items() if k not in VOLATILE}


@pytest.fixture(scope="module")
def paper_study() -> cd.MarginsResult:
    """The shipped controller on the paper's plant (an immutable result the tests read)."""
    return cd.margins(samples=SAMPLES)


def test_python_and_command_line_give_the_same_study_and_folder(
    paper_study: cd.MarginsResult, tmp_path: Path
) -> None:
    out = tmp_path / "cli"
    result = CliRunner().invoke(
        main,
        ["margins", "--samples", str(SAMPLES), "--out", str(out), "--json", "--no-plots"],
        catch_exceptions=False,
    )
    assert result.exit_code == 0, result.output
    from_cli = json.loads(result.stdout)
    assert from_cli["out_dir"] == str(out.absolute())
    assert _without_volatile(paper_study.summary.to_json()) == _without_volatile(from_cli)
    # The figures are test_plot_returns_the_figures_save_writes_and_writes_nothing's.
    saved = paper_study.save(tmp_path / "python", plots=False)
    cli_files = sorted(p.name for p in out.iterdir())
    assert sorted(p.name for p in saved.iterdir()) == cli_files
    assert {"summary.json", "sampled_margins.csv"} <= set(cli_files)
    written = json.loads((saved / "summary.json").read_text())
    assert written["out_dir"] == str(saved.absolute())
    np.testing.assert_array_equal(
        np.loadtxt(saved / "sampled_margins.csv", delimiter=",", skiprows=1),
        np.loadtxt(out / "sampled_margins.csv", delimiter=",", skiprows=1),
    )


def test_phase_margins_are_the_loops_broken_one_at_a_time(paper_study: cd.MarginsResult) -> None:
    # Each input channel's loop with the other two closed, from the plant and the
    # controller's own frequency responses (python-control), crossover by root finding.
    summary = paper_study.summary
    plant = linearize(
        build_model(paper_study.problem, modes=summary.analysis_plant_modes),
        sensor=True,
        units="deg_mNm",
    )
    controller = paper_study.record.reduced

    def loop(i: int, omega: float) -> complex:
        full = controller(1j * omega) @ plant(1j * omega)
        others = [j for j in range(3) if j != i]
        closed = np.linalg.solve(np.eye(2) + full[np.ix_(others, others)], full[others, i])
        return complex(full[i, i] - full[i, others] @ closed)

    for i, axis in enumerate("xyz"):
        channel = summary.per_channel[axis]
        guess = channel["crossover_rad_s"]
        crossover = brentq(lambda w, i=i: abs(loop(i, w)) - 1.0, guess / 2, guess * 2)
        phase_margin = 180.0 + np.degrees(np.angle(loop(i, crossover)))
        assert channel["crossover_rad_s"] == pytest.approx(crossover, rel=1e-9)
        assert channel["phase_margin_deg"] == pytest.approx(phase_margin, rel=1e-9)
        assert channel["delay_margin_s"] == pytest.approx(
            np.radians(phase_margin) / crossover, rel=1e-9
        )
    assert summary.nominal.phase_margin_deg == min(
        c["phase_margin_deg"] for c in summary.per_channel.values()
    )


def test_plot_returns_the_figures_save_writes_and_writes_nothing(
    paper_study: cd.MarginsResult, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import matplotlib.pyplot as plt

    monkeypatch.chdir(tmp_path)
    figures = paper_study.plot()
    assert set(figures) == {"mu", "uncertainty_weight", "loop_shapes", "margins"}
    assert list(tmp_path.iterdir()) == []
    # The scatter shows every stable sampled plant's x channel: gain [dB] against phase [deg].
    scatter = figures["margins"].axes[0].collections[0]
    stable = paper_study.study.sampled[~paper_study.study.unstable]
    np.testing.assert_allclose(scatter.get_offsets(), stable[:, 0, [1, 0]])
    for figure in figures.values():
        plt.close(figure)


def test_another_plant_takes_the_shipped_controller_only_when_asked(tmp_path: Path) -> None:
    with pytest.raises(ControllerMismatchError, match="--allow-mismatch"):
        cd.margins("side_engines_12", samples=2)
    study = cd.margins("side_engines_12", samples=2, allow_mismatch=True)
    assert study.summary.problem == "side_engines_12"
    assert study.summary.plant_sha256 != study.summary.controller_plant_sha256
    arguments = ["side_engines_12", "--samples", "2", "--allow-mismatch", "--no-plots"]
    result = CliRunner().invoke(
        main,
        ["margins", *arguments, "--out", str(tmp_path / "side"), "--json"],
        catch_exceptions=False,
    )
    assert result.exit_code == 0, result.output
    assert _without_volatile(study.summary.to_json()) == _without_volatile(
        json.loads(result.stdout)
    )
    study.save(tmp_path / "python", plots=False)
    assert sorted(p.name for p in (tmp_path / "python").iterdir()) == sorted(
        p.name for p in (tmp_path / "side").iterdir()
    )
