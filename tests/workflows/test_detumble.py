"""``casadi_debris.detumble`` is the ``detumble`` command: the same run from Python as from
the command line, the same folder from ``save``, and its figure drawn from its arrays."""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main


def _without_wall_time(summary: dict) -> dict:
    summary.pop("wall_time_s")
    return summary


@pytest.mark.parametrize(
    ("name", "rate", "keywords", "options"),
    [
        ("paper", (0.02, 0.03, -0.02), {}, []),
        (
            "side_engines_12",
            (-0.01, 0.02, 0.01),
            {"period_s": 0.5, "gain_per_s": 0.05},
            ["--period-s", "0.5", "--gain-per-s", "0.05"],
        ),
    ],
)
def test_python_and_command_line_give_the_same_detumble(
    name: str,
    rate: tuple[float, float, float],
    keywords: dict[str, float],
    options: list[str],
    tmp_path: Path,
) -> None:
    result = cd.detumble(name, rate_rad_s=rate, ocp=False, **keywords)
    assert isinstance(result, cd.DetumbleResult)
    np.testing.assert_array_equal(result.run.rate_rad_s[0], rate)
    out = tmp_path / "cli"
    arguments = ["detumble", name, "--rate-rad-s", ",".join(map(str, rate)), *options]
    printed = CliRunner().invoke(main, [*arguments, "--no-ocp", "--out", str(out), "--json"])
    assert printed.exit_code == 0, printed.output
    from_cli = _without_wall_time(json.loads(printed.stdout))
    assert from_cli.pop("out_dir") == str(out.absolute())
    from_python = _without_wall_time(result.summary.to_json())
    assert from_python.pop("out_dir") is None
    assert from_cli == from_python

    saved = result.save(tmp_path / "python")
    assert sorted(p.name for p in saved.iterdir()) == sorted(p.name for p in out.iterdir())
    assert (saved / "series.csv").read_text() == (out / "series.csv").read_text()
    written = json.loads((saved / "summary.json").read_text())
    assert written["out_dir"] == str(saved.absolute())


def test_plot_draws_the_run_it_holds_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    result = cd.detumble(rate_rad_s=(0.01, 0.01, 0.01), ocp=False)
    monkeypatch.chdir(tmp_path)
    figures = result.plot()
    assert set(figures) == {"detumble"}
    assert list(tmp_path.iterdir()) == []
    fuel_axes = figures["detumble"].axes[2]
    heights = [bar.get_height() for bar in fuel_axes.patches]
    np.testing.assert_allclose(heights, np.asarray(result.summary.run.fuel_per_cubesat_kg) * 1e3)
    plt.close(figures["detumble"])
    saved = result.save(tmp_path / "no-plots", plots=False)
    assert sorted(p.name for p in saved.iterdir() if not p.name.startswith(".")) == [
        "series.csv",
        "summary.json",
    ]
