"""``casadi_debris.mission`` is the ``mission`` command: the same mission from Python as
from the command line, the same folder from ``save``, and its figures returned."""

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

# A slow tumble, so that the detumble is flown in seconds, not hours.
SLOW_TUMBLE = "\n\n[detumble]\ninitial_rate_rad_s = [0.01, -0.01, 0.01]\n"


@pytest.mark.parametrize(
    ("base", "solar"),
    [
        ("paper", ("high",)),
        # Another swarm, two solar cases: under -m slow (10 s).
        pytest.param("fewer_stronger", ("mean", "high"), marks=pytest.mark.slow),
    ],
)
def test_python_and_command_line_give_the_same_mission(
    base: str, solar: tuple[str, ...], tmp_path: Path
) -> None:
    path = tmp_path / f"{base}_slow.toml"
    path.write_text(f'extends = "{base}"\nname = "{base}_slow"{SLOW_TUMBLE}')
    lines: list[str] = []
    result = cd.mission(path, solar=solar, limit_years=5.0, progress=lines.append)
    assert isinstance(result, cd.MissionResult) and len(lines) == 1
    assert list(result.summary.reentry_years) == list(solar)
    out = tmp_path / "cli"
    printed = CliRunner().invoke(
        main, ["-q", "mission", str(path), "--solar", ",".join(solar), "--out", str(out), "--json"]
    )
    assert printed.exit_code == 0, printed.output
    assert json.loads(printed.stdout) == result.summary.to_json()

    saved = result.save(tmp_path / "python")
    assert sorted(p.name for p in saved.iterdir()) == sorted(p.name for p in out.iterdir())
    assert json.loads((saved / "summary.json").read_text()) == result.summary.to_json()
    assert (saved / "phases.csv").read_text() == (out / "phases.csv").read_text()


def test_plot_returns_the_figures_save_writes_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "slow.toml"
    path.write_text(f'extends = "paper"\nname = "slow"{SLOW_TUMBLE}')
    result = cd.mission(path, solar=("mean",))
    monkeypatch.chdir(tmp_path)
    before = set(tmp_path.iterdir())
    figures = result.plot()
    assert set(figures) == {"mission", "altitude", "decay"}
    assert set(tmp_path.iterdir()) == before
    # The decay panel's perigee line starts at the flown case's first perigee.
    (trajectory,) = result.mission.trajectories
    line = figures["decay"].axes[0].lines[0]
    assert np.asarray(line.get_ydata())[0] == pytest.approx(
        trajectory.history.perigee_altitude_m[0] / M_PER_KM, rel=1e-12
    )
    assert np.asarray(line.get_xdata())[-1] == pytest.approx(
        trajectory.history.time_s[-1] / SECONDS_PER_YEAR
    )
    for figure in figures.values():
        plt.close(figure)
    with pytest.raises(cd.CasadiDebrisError, match="solar"):
        cd.mission(path, solar=("medium",))
