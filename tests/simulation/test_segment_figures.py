"""A run's figures segment by segment add up to the run's own."""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest

from casadi_debris.config import default_controller_path, problem_from_dict
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import segment_figures, simulate_closed_loop


def test_segments_tile_the_run(fresh_data: dict[str, Any]) -> None:
    fresh_data["simulation"] |= {
        "reference": "sequence",
        "duration_s": 500.0,
        "segments": [
            {"kind": "hold", "duration_s": 50.0},
            {"kind": "slew", "axis": "z", "angle_deg": 10.0, "duration_s": 300.0},
        ],
    }
    problem = problem_from_dict(fresh_data, "<test>")
    controller = Controller.from_dict(json.loads(default_controller_path().read_text()))
    reference = scenario_reference(problem)
    result = simulate_closed_loop(build_model(problem), controller.reduced, reference)
    figures = segment_figures(result, reference.pieces)
    assert [(f.segment, f.kind, f.start_s, f.end_s) for f in figures] == [
        (1, "hold", 0.0, 50.0),
        (2, "slew", 50.0, 350.0),
        (None, "hold", 350.0, 500.0),
    ]
    summary = result.summary()
    assert sum(f.fuel_kg for f in figures) == pytest.approx(summary.fuel_kg, rel=1e-12)
    assert max(f.max_error_deg for f in figures) == pytest.approx(summary.max_error_deg)
    during = (result.time_s >= 50.0) & (result.time_s <= 350.0)
    assert figures[1].max_error_arcsec == pytest.approx(
        np.degrees(np.abs(result.error_rad[during]).max()) * 3600.0
    )
