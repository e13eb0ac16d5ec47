"""The statistics figure: drawn for a large campaign and for one too small to rank, without
matplotlib's layout warnings."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from casadi_debris.campaigns import campaign_statistics
from casadi_debris.plots import plot_statistics


@pytest.mark.parametrize("count", [2, 50])
def test_the_figure_is_drawn_whole(tmp_path: Path, count: int) -> None:
    rng = np.random.default_rng(count)
    quantities = {
        "mass_kg": rng.uniform(600, 700, count),
        "inertia_scale_z": rng.uniform(size=count),
    }
    figures = {
        "max_error_deg": 0.4 + 0.3 * quantities["inertia_scale_z"],
        "fuel_slew_kg": 3e-4 + 1e-5 * rng.standard_normal(count),
    }
    ids = [f"varied-{i:04d}" for i in range(count)]
    statistics = campaign_statistics(ids, figures, quantities, ("max_error_deg", 0.6))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        path = plot_statistics(statistics, figures, tmp_path / "statistics.png", title="t")
    assert path.stat().st_size > 20_000
