"""``casadi_debris.placement`` is the ``placement`` command: the same study from Python as
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
from casadi_debris.geometry import build_geometry, torque_authority

VOLATILE = ("out_dir", "solver")  # the MILP's wall time


def _steady(summary: dict) -> dict:
    return {k: v for k, v in summary.items() if k not in VOLATILE}


@pytest.mark.parametrize(
    ("name", "keywords", "options"),
    [
        (
            "paper",
            {"count": 4, "candidates": 1, "time_limit": 60.0},
            ["--count", "4", "--candidates", "1", "--time-limit", "60"],
        ),
        (
            "three_faces",
            {
                "count_range": (4, 6),
                "candidates": (1, 2),
                "max_added_inertia": 200.0,
                "pareto_counts": [4, 6],
                "time_limit": 60.0,
            },
            [
                "--count-range",
                "4:6",
                "--candidates",
                "1x2",
                "--max-added-inertia",
                "200",
                "--pareto",
                "4,6",
                "--time-limit",
                "60",
            ],
        ),
    ],
)
def test_python_and_command_line_give_the_same_placement(
    name: str, keywords: dict, options: list[str], tmp_path: Path
) -> None:
    result = cd.placement(name, **keywords)
    assert isinstance(result, cd.PlacementResult)
    out = tmp_path / "cli"
    printed = CliRunner().invoke(
        main, ["placement", name, *options, "--out", str(out), "--json"], catch_exceptions=False
    )
    assert printed.exit_code == 0, printed.output
    from_cli = json.loads(printed.stdout)
    assert from_cli["out_dir"] == str(out.absolute())
    from_python = result.summary.to_json()
    assert _steady(from_cli) == _steady(from_python)
    assert from_cli["solver"]["optimal"] == from_python["solver"]["optimal"]

    saved = result.save(tmp_path / "python")
    names = sorted(p.name for p in saved.iterdir())
    assert names == sorted(p.name for p in out.iterdir())
    assert ("pareto.png" in names) == ("pareto_counts" in keywords)
    # The written layout loads to the authority the study judged.
    placed = cd.load_problem(saved / "placement.toml")
    authority = torque_authority(build_geometry(placed), zero_net_force=True)
    for axis, value in result.study.metrics.authority_Nm.items():
        assert authority[axis] == pytest.approx(value, rel=1e-9)


def test_plot_returns_the_layout_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    result = cd.placement(count=6, candidates=(2, 2), time_limit=60.0)
    monkeypatch.chdir(tmp_path)
    figures = result.plot()
    assert set(figures) == {"layout"}
    assert list(tmp_path.iterdir()) == []
    assert len(result.study.chosen) == 6
    # Every chosen CubeSat is a filled dot in the two views that see its face edge on.
    from casadi_debris.plots import VIEWS

    dots = 0
    for axis, (first, second) in zip(figures["layout"].axes, VIEWS, strict=False):
        drawn = sorted(
            (float(line.get_xdata()[0]), float(line.get_ydata()[0]))
            for line in axis.lines
            if line.get_marker() == "o"
        )
        dots += len(drawn)
        for point in drawn:
            assert any(
                np.allclose(point, c.cubesat.position_corner_m[[first, second]])
                for c in result.study.chosen
            )
    assert dots == 2 * len(result.study.chosen)
    plt.close(figures["layout"])


@pytest.mark.parametrize(
    ("keywords", "words"),
    [
        ({"count": 4, "count_range": (2, 4)}, "--count"),
        ({"count_range": (5, 4)}, "--count-range"),
        ({"side_engines": (3,)}, "--side-engines"),
        ({"max_added_inertia": (1.0, 2.0)}, "--max-added-inertia"),
        ({"pareto_counts": "all"}, "--pareto"),
        ({"objective": "best-axis"}, "objective"),
    ],
)
def test_bad_keywords_are_named(keywords: dict, words: str) -> None:
    with pytest.raises(cd.CasadiDebrisError, match=words):
        cd.placement(**keywords)
