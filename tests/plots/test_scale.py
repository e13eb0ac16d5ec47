"""Figures scale to their data: a requirement or an authority far beyond the data is said
to be off scale, not drawn so that the data become a flat line or one bar."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.lines import Line2D

import casadi_debris.plots._simulation as simulation_plots
import casadi_debris.plots._statistics as statistics_plots
from casadi_debris.campaigns import campaign_statistics


def _kept(monkeypatch, module) -> list:
    """The figures ``module`` saves, kept open for the test to read."""
    figures: list = []
    real = module.save_figure

    def keep(figure, path):
        figures.append(figure)
        figure.canvas.draw()  # limits and texts settled as written
        limits = [(axis.get_xlim(), axis.get_ylim()) for axis in figure.axes]
        texts = [[t.get_text() for t in axis.texts] for axis in figure.axes]
        lines = [[line for line in axis.lines if isinstance(line, Line2D)] for axis in figure.axes]
        figures[-1] = SimpleNamespace(limits=limits, texts=texts, lines=lines)
        return real(figure, path)

    monkeypatch.setattr(module, "save_figure", keep)
    return figures


def _run(error_peak_rad: float, torque_peak_Nm: float) -> SimpleNamespace:
    """A closed-loop run's drawn series: a damped error and torque of the given peaks."""
    time_s = np.linspace(0.0, 600.0, 601)
    shape = np.exp(-time_s / 100.0) * np.sin(time_s / 30.0)
    shape /= np.abs(shape).max()
    error = np.column_stack([0.2 * shape, 0.5 * shape, shape]) * error_peak_rad
    torque = np.column_stack([shape, 0.3 * shape, 0.6 * shape])[:-1] * torque_peak_Nm
    return SimpleNamespace(
        time_s=time_s,
        reference_BN=np.tile([1.0, 0.0, 0.0, 0.0], (len(time_s), 1)),
        error_rad=error,
        torque_Nm=torque,
        authority_time_s=np.array([0.0]),
        authority_Nm=np.array([[4.6e-3, 4.6e-3, 2.0e-3, 2.0e-3, 4.3e-3, 4.3e-3]]),
    )


@pytest.mark.parametrize(
    ("error_deg", "torque_mNm", "requirement_drawn", "authority_drawn"),
    [(0.03, 0.05, False, False), (0.4, 3.0, True, True), (0.03, 1.5, False, True)],
)
def test_closed_loop_panels_scale_to_the_data(
    tmp_path: Path, monkeypatch, error_deg, torque_mNm, requirement_drawn, authority_drawn
) -> None:
    drawn = _kept(monkeypatch, simulation_plots)
    run = _run(np.radians(error_deg), torque_mNm * 1e-3)
    simulation_plots.plot_closed_loop(run, tmp_path / "c.png", requirement=0.6)  # type: ignore[arg-type]
    [figure] = drawn
    (_, (error_low, error_high)), (_, (torque_low, torque_high)) = figure.limits[1:3]
    # The data always fill a good part of the panel: read apart from the figure code.
    assert error_high - error_low < 4.0 * 2.0 * error_deg
    assert torque_high - torque_low < 4.0 * 2.0 * max(torque_mNm, 4.6 if authority_drawn else 0)
    assert min(error_high, -error_low) >= error_deg
    # The requirement: lines at +-0.6 in range, else a note that gives it.
    at_requirement = [
        line for line in figure.lines[1] if np.allclose(np.abs(line.get_ydata()), 0.6)
    ]
    assert (len(at_requirement) == 2) == requirement_drawn
    assert (error_high >= 0.6) == requirement_drawn
    noted = " ".join(figure.texts[1])
    assert ("requirement ±0.6 deg: off scale" in noted) == (not requirement_drawn)
    authority_noted = " ".join(figure.texts[2])
    assert ("authority (dotted) off scale: at least 2 mNm" in authority_noted) == (
        not authority_drawn
    )
    assert (torque_high >= 2.0) == authority_drawn


@pytest.mark.parametrize(("spread", "requirement_drawn"), [(0.002, False), (0.3, True)])
def test_the_histogram_spreads_over_the_cases_not_to_a_far_requirement(
    tmp_path: Path, monkeypatch, spread: float, requirement_drawn: bool
) -> None:
    rng = np.random.default_rng(7)  # seed recorded: the draws are the test's data
    count = 200
    quantities = {"mass_kg": rng.uniform(600, 700, count), "scale_z": rng.uniform(size=count)}
    figures = {
        "max_error_deg": 0.35 + spread * quantities["scale_z"],
        "fuel_slew_kg": 3e-4 + 1e-5 * rng.standard_normal(count),
    }
    ids = [f"varied-{i:04d}" for i in range(count)]
    statistics = campaign_statistics(ids, figures, quantities, ("max_error_deg", 0.6))
    drawn = _kept(monkeypatch, statistics_plots)
    statistics_plots.plot_statistics(statistics, figures, tmp_path / "s.png", title="t")
    [figure] = drawn
    (low, high), _ = figure.limits[0]
    values = figures["max_error_deg"]
    # The cases span at least a third of the axis: many bars, not one.
    assert (values.max() - values.min()) / (high - low) > (0.3 if requirement_drawn else 0.5)
    requirement_lines = [line for line in figure.lines[0] if np.allclose(line.get_xdata(), 0.6)]
    assert bool(requirement_lines) == requirement_drawn == (high >= 0.6)
    assert ("requirement 0.6, off scale" in " ".join(figure.texts[0])) == (not requirement_drawn)


@pytest.mark.parametrize(("peak", "drawn"), [(50.0, True), (10.0, False), (0.0, True)])
def test_a_one_sided_limit_is_drawn_in_range_and_noted_beyond(peak: float, drawn: bool) -> None:
    """As the burn's pointing panel: errors from 0 up, the requirement 60 arcsec."""
    import matplotlib.pyplot as plt

    from casadi_debris.plots import limit_line

    figure, axes = plt.subplots()
    axes.plot([0.0, 1.0, 2.0], [0.0, peak, 0.5 * peak])
    assert limit_line(axes, 60.0, peak, "requirement 60 arcsec", "error", both_signs=False) == drawn
    at_limit = [line for line in axes.lines if np.allclose(line.get_ydata(), 60.0)]
    assert len(at_limit) == int(drawn)
    if not drawn:
        low, high = axes.get_ylim()
        assert low == 0.0 and peak < high < 60.0
        [note] = axes.texts
        assert note.get_text() == "↑ requirement 60 arcsec: off scale, 6 × the largest error"
    plt.close(figure)
