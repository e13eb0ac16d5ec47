"""``casadi_debris.alternatives`` is the ``alternatives`` command: the same comparison from
Python as from the command line, the same folder from ``save``, and its figure returned."""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest
from click.testing import CliRunner

import casadi_debris as cd
from casadi_debris.cli import main

VOLATILE = ("wall_time_s", "out_dir")


@pytest.mark.parametrize(
    ("designs", "max_failed"),
    [(["paper"], 1), (["side_engines_12", "two_per_face"], 0)],
)
def test_python_and_command_line_give_the_same_comparison(
    designs: list[str], max_failed: int, tmp_path: Path
) -> None:
    names: list[str] = []
    result = cd.alternatives(designs, max_failed=max_failed, progress=names.append)
    assert isinstance(result, cd.AlternativesResult) and names == designs
    out = tmp_path / "cli"
    arguments = ["-q", "alternatives", *designs, "--max-failed", str(max_failed)]
    printed = CliRunner().invoke(main, [*arguments, "--out", str(out), "--json"])
    assert printed.exit_code == 0, printed.output
    from_cli = json.loads(printed.stdout)
    assert from_cli["out_dir"] == str(out.absolute())
    from_python = result.summary.to_json()
    for volatile in VOLATILE:
        from_cli.pop(volatile), from_python.pop(volatile)
    assert from_cli == json.loads(json.dumps(from_python))

    saved = result.save(tmp_path / "python")
    assert sorted(p.name for p in saved.iterdir()) == sorted(p.name for p in out.iterdir())
    assert (saved / "alternatives.csv").read_text() == (out / "alternatives.csv").read_text()


def test_plot_draws_each_designs_weakest_ratio_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    result = cd.alternatives([cd.load_problem("paper"), "fewer_stronger"], max_failed=0)
    monkeypatch.chdir(tmp_path)
    figures = result.plot()
    assert set(figures) == {"alternatives"}
    assert list(tmp_path.iterdir()) == []
    bars = figures["alternatives"].axes[0].containers[0]
    np.testing.assert_allclose(
        [bar.get_height() for bar in bars], [d.weakest_ratio for d in result.summary.designs]
    )
    plt.close(figures["alternatives"])
    with pytest.raises(cd.CasadiDebrisError, match="max-failed"):
        cd.alternatives(["paper"], max_failed=3)
