"""``casadi_debris.deorbit`` is the ``deorbit`` command: the same plan from Python as from
the command line, the same folder from ``save``, and its figures drawn from its arrays."""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main
from casadi_debris.units import M_PER_KM, SECONDS_PER_YEAR

CASES = [
    ("paper", ("high",), ["--solar", "high"]),
    ("fewer_stronger", ("mean", "high"), ["--solar", "mean,high", "--held"]),
]


@pytest.mark.parametrize(("name", "solar", "options"), CASES)
def test_python_and_command_line_give_the_same_plan(
    name: str, solar: tuple[str, ...], options: list[str], tmp_path: Path
) -> None:
    held = "--held" in options
    result = cd.deorbit(name, solar=solar, held=held, minimum_swarm=False, workers=1)
    assert isinstance(result, cd.DeorbitResult)
    out = tmp_path / "cli"
    arguments = ["deorbit", name, *options, "--no-minimum-swarm", "--workers", "1"]
    printed = CliRunner().invoke(main, [*arguments, "--out", str(out), "--json"])
    assert printed.exit_code == 0, printed.output
    from_cli = json.loads(printed.stdout)
    assert from_cli.pop("out_dir") == str(out.absolute())
    from_python = result.summary.to_json()
    assert from_python.pop("out_dir") is None
    assert from_cli == from_python
    assert set(from_python["reentry_years"]) == set(solar)

    saved = result.save(tmp_path / "python")
    assert sorted(p.name for p in saved.iterdir()) == sorted(p.name for p in out.iterdir())
    written = json.loads((saved / "summary.json").read_text())
    assert written.pop("out_dir") == str(saved.absolute())
    assert written == from_python


def test_plot_draws_each_case_from_its_decay_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    result = cd.deorbit(solar=("low", "high"), minimum_swarm=False, workers=1)
    figures = result.plot()
    assert set(figures) == {"decay", "lifetime_vs_dv"}
    assert list(tmp_path.iterdir()) == []
    lines = {line.get_label(): line for line in figures["decay"].axes[0].lines}
    for item in result.trajectories:
        line = lines[f"{item.solar}: perigee (band to apogee)"]
        history = item.history
        # The perigee line is the flown decay resampled over its own time span.
        x, y = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
        assert x[0] == 0.0 and x[-1] == pytest.approx(history.time_s[-1] / SECONDS_PER_YEAR)
        assert y[0] == pytest.approx(history.perigee_altitude_m[0] / M_PER_KM, rel=1e-12)
        assert y[-1] == pytest.approx(history.perigee_altitude_m[-1] / M_PER_KM, rel=1e-12)
    curve = figures["lifetime_vs_dv"].axes[0].lines[0]
    np.testing.assert_array_equal(curve.get_xdata(), result.trajectories[0].dv_m_s)
    for figure in figures.values():
        plt.close(figure)


def test_an_unknown_solar_case_is_named() -> None:
    with pytest.raises(cd.CasadiDebrisError, match="solar"):
        cd.deorbit(solar=("extreme",))
