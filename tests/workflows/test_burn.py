"""``casadi_debris.burn`` is the ``burn`` command: the same burn from Python as from the
command line, the same folder from ``save``, and its figure drawn from its series."""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main
from casadi_debris.units import ARCSEC_PER_RAD

VOLATILE = ("wall_time_s", "out_dir")


def _steady(summary: dict) -> dict:
    return {k: v for k, v in summary.items() if k not in VOLATILE}


@pytest.mark.parametrize(
    ("name", "keywords", "options"),
    [
        (
            "paper",
            {"direction": "normal", "hours": 0.005, "thrust_fraction": 0.5},
            ["--direction", "normal", "--hours", "0.005", "--thrust-fraction", "0.5"],
        ),
        (
            "paper_burn",
            {"hours": 0.004, "body_axis": "-y", "first_stage_left_s": 3.0},
            ["--hours", "0.004", "--body-axis", "-y", "--first-stage-left-s", "3"],
        ),
    ],
)
def test_python_and_command_line_give_the_same_burn(
    name: str, keywords: dict, options: list[str], tmp_path: Path
) -> None:
    lines: list[str] = []
    result = cd.burn(name, progress=lines.append, **keywords)
    assert isinstance(result, cd.BurnResult) and len(lines) == 1
    out = tmp_path / "cli"
    printed = CliRunner().invoke(main, ["burn", name, *options, "--out", str(out), "--json"])
    assert printed.exit_code == 0, printed.output
    from_cli = json.loads(printed.stdout)
    assert from_cli["out_dir"] == str(out.absolute())
    assert _steady(from_cli) == _steady(result.summary.to_json())
    assert result.summary.out_dir is None

    saved = result.save(tmp_path / "python")
    assert sorted(p.name for p in saved.iterdir()) == sorted(p.name for p in out.iterdir())
    assert (saved / "series.csv").read_text() == (out / "series.csv").read_text()


def test_plot_draws_the_pointing_error_it_holds_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    result = cd.burn(hours=0.003)
    monkeypatch.chdir(tmp_path)
    figures = result.plot()
    assert set(figures) == {"burn"}
    assert list(tmp_path.iterdir()) == []
    drawn = figures["burn"].axes[0].lines[0]
    np.testing.assert_allclose(drawn.get_ydata(), result.run.pointing_error_rad * ARCSEC_PER_RAD)
    np.testing.assert_allclose(drawn.get_xdata(), result.run.result.time_s / 60.0)
    plt.close(figures["burn"])


def test_a_fraction_and_a_thrust_together_and_a_zero_axis_are_refused() -> None:
    with pytest.raises(cd.CasadiDebrisError, match="thrust-mN"):
        cd.burn(hours=0.001, thrust_fraction=0.5, thrust_mN=1.0)
    with pytest.raises(cd.CasadiDebrisError, match="body-axis"):
        cd.burn(hours=0.001, body_axis=(0.0, 0.0, 0.0))
