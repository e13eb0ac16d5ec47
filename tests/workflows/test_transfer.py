"""``casadi_debris.transfer`` is the ``transfer`` command: the same plan from Python as
from the command line, the same folder from ``save``, and its figure drawn from its
trajectories."""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main
from casadi_debris.units import SECONDS_PER_DAY

VOLATILE = ("ocp_solve_time_s", "out_dir")


def _short(tmp_path: Path, base: str, altitude_km: float, inclination_deg: float) -> Path:
    """A short transfer up to the debris' orbit (685 km, 98.1 deg), planned in seconds."""
    path = tmp_path / f"{base}_short.toml"
    path.write_text(
        f'extends = "{base}"\nname = "{base}_short"\n\n[transfer]\n'
        f"from_altitude_km = {altitude_km}\nfrom_inclination_deg = {inclination_deg}\n"
        "to_altitude_km = 685.0\nto_inclination_deg = 98.1\n"
    )
    return path


def _steady(summary: dict) -> dict:
    return {k: v for k, v in summary.items() if k not in VOLATILE}


@pytest.mark.parametrize(
    ("base", "altitude_km", "inclination_deg", "objective"),
    [
        ("paper", 675.0, 98.1, "time"),
        # Another swarm and objective: under -m slow (14 s).
        pytest.param("fewer_stronger", 680.0, 98.05, "propellant", marks=pytest.mark.slow),
    ],
)
def test_python_and_command_line_give_the_same_transfer(
    base: str, altitude_km: float, inclination_deg: float, objective: str, tmp_path: Path
) -> None:
    path = _short(tmp_path, base, altitude_km, inclination_deg)
    result = cd.transfer(path, objective=objective)  # type: ignore[arg-type]
    assert isinstance(result, cd.TransferResult)
    assert result.summary.objective == objective
    out = tmp_path / "cli"
    arguments = ["transfer", str(path), "--objective", objective, "--out", str(out), "--json"]
    printed = CliRunner().invoke(main, arguments)
    assert printed.exit_code == 0, printed.output
    from_cli = json.loads(printed.stdout)
    assert from_cli["out_dir"] == str(out.absolute())
    assert _steady(from_cli) == _steady(result.summary.to_json())

    saved = result.save(tmp_path / "python")
    assert sorted(p.name for p in saved.iterdir()) == sorted(p.name for p in out.iterdir())
    assert (saved / "guidance.csv").read_text() == (out / "guidance.csv").read_text()


def test_plot_draws_the_guidance_it_holds_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    result = cd.transfer(_short(tmp_path, "paper", 680.0, 98.1))
    monkeypatch.chdir(tmp_path)
    before = set(tmp_path.iterdir())
    figures = result.plot()
    assert set(figures) == {"transfer"}
    assert set(tmp_path.iterdir()) == before
    guided = result.plan.guided
    days = [np.asarray(line.get_xdata()) for line in figures["transfer"].axes[0].lines]
    # The guidance law's altitude line spans the guided trajectory's days.
    assert any(
        len(x) == len(guided.time_s) and np.allclose(x, guided.time_s / SECONDS_PER_DAY)
        for x in days
    )
    plt.close(figures["transfer"])
    with pytest.raises(cd.ProblemFileError, match="nothing to do"):
        cd.transfer(_short(tmp_path, "paper", 685.0, 98.1))
