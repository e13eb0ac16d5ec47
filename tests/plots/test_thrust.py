"""The thrust figure: a panel per face, a colour per CubeSat, a line style per engine of a
CubeSat, and a legend beside the panel (not over the lines) that names them from 1."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.colors import to_hex

import casadi_debris.plots._simulation as simulation_plots
from casadi_debris import load_problem
from casadi_debris.geometry import build_geometry
from casadi_debris.report import engine_groups


def _run(problem_name: str, failed: tuple[int, ...] = ()) -> tuple[SimpleNamespace, dict, list]:
    problem = load_problem(problem_name)
    geometry = build_geometry(problem)
    owners = np.array([engine.cubesat for engine in geometry.engines])
    time_s = np.linspace(0.0, 100.0, 101)
    rng = np.random.default_rng(11)  # seeded: the thrust is only something to draw
    thrust = rng.uniform(0.0, 0.6e-3, (len(time_s) - 1, len(owners)))
    failed_mask = np.isin(np.arange(len(geometry.cubesats)), failed)
    run = SimpleNamespace(
        time_s=time_s,
        thrust_N=thrust,
        propulsion=SimpleNamespace(failed_cubesats=failed_mask, engine_cubesat=owners),
        fuel_per_cubesat_kg=rng.uniform(0.0, 1e-5, len(geometry.cubesats)),
    )
    return run, engine_groups(problem), [engine.cubesat for engine in geometry.engines]


def _dashes(line) -> tuple:
    """A line's dash pattern (``get_linestyle`` names every custom pattern "--")."""
    offset, pattern = line._unscaled_dash_pattern
    return (offset, tuple(pattern) if pattern is not None else None)


@pytest.mark.parametrize(("name", "failed"), [("paper", (4,)), ("side_engines_12", ())])
def test_lines_are_coloured_by_cubesat_and_styled_by_engine(
    tmp_path: Path, monkeypatch, name: str, failed: tuple[int, ...]
) -> None:
    run, groups, owner_of = _run(name, failed)
    seen: list = []

    def keep(figure, path):
        figure.tight_layout()
        figure.canvas.draw()
        panels = []
        for axis in figure.axes[: len(groups)]:
            legend = axis.get_legend()
            panels.append(
                (
                    [(to_hex(line.get_color()), _dashes(line)) for line in axis.lines],
                    [text.get_text() for text in legend.get_texts()],
                    legend.get_window_extent().x0 >= axis.get_window_extent().x1,
                )
            )
        seen.append(panels)
        return path

    monkeypatch.setattr(simulation_plots, "save_figure", keep)
    simulation_plots.plot_thrust(run, tmp_path / "thrust.png", groups)  # type: ignore[arg-type]
    [panels] = seen
    for (lines, legend, beside), engines in zip(panels, groups.values(), strict=True):
        indices = [engine for engine, _ in engines]
        owners = [owner_of[e] for e in indices]
        assert len(lines) == len(indices) and beside
        for (colour_a, style_a), a, owner_a in zip(lines, indices, owners, strict=True):
            for (colour_b, style_b), b, owner_b in zip(lines, indices, owners, strict=True):
                if a < b:
                    # Same CubeSat: same colour, another style; another CubeSat: another colour.
                    assert (colour_a == colour_b) == (owner_a == owner_b)
                    if owner_a == owner_b:
                        assert style_a != style_b
        names = [
            f"CubeSat {c + 1}" + (" (failed)" if c in failed else "") for c in dict.fromkeys(owners)
        ]
        several = max(owners.count(c) for c in owners)
        styles = [f"engine {k + 1}" for k in range(several)] if several > 1 else []
        assert legend == names + styles
