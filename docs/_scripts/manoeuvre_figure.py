"""The figure and the numbers of the manoeuvre section of docs/guide/slews.md.

Run from anywhere (the package must import: installed, or ``PYTHONPATH=src``)::

    python docs/_scripts/manoeuvre_figure.py

Flies ``problems/paper_sequence.toml`` (90 deg about [1, 1, 1], a hold, a slew onto
nadir, nadir tracking) in closed loop, nominal plant, as ``casadi-debris simulate
paper_sequence`` does, and writes ``docs/figures/manoeuvre_paper_sequence.png``: the
reference's 3-2-1 angles, the attitude error and the torque, each segment shaded.
Prints each segment's window, largest error and fuel as JSON. Takes about a minute.
"""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np

from casadi_debris import load_problem
from casadi_debris.config import default_controller_path
from casadi_debris.dynamics import build_model, euler_angles_321
from casadi_debris.guidance import scenario_reference, segment_records
from casadi_debris.plots import plot_segment_series
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import segment_figures, simulate_closed_loop
from casadi_debris.units import MNM_PER_NM

FIGURES = Path(__file__).resolve().parents[1] / "figures"


def main() -> None:
    problem = load_problem("paper_sequence")
    record = Controller.from_dict(json.loads(default_controller_path().read_text()))
    reference = scenario_reference(problem)
    result = simulate_closed_loop(build_model(problem), record.reduced, reference)
    records = segment_records(reference.pieces)
    time = result.time_s
    plot_segment_series(
        time,
        [
            ("reference 3-2-1 angles [deg]", np.degrees(euler_angles_321(result.reference_BN))),
            ("attitude error [deg]", np.degrees(result.error_rad)),
            ("torque [mNm]", result.torque_Nm * MNM_PER_NM),
        ],
        records,
        FIGURES / "manoeuvre_paper_sequence.png",
        "90° about [1, 1, 1], hold, slew onto nadir, nadir track (nominal plant)",
    )
    figures = segment_figures(result, reference.pieces)
    rows = [
        {**slew.to_json(), "fuel_open_loop_kg": slew.fuel_kg, **figure.to_json()}
        for slew, figure in zip(records, figures, strict=True)
    ]
    summary = result.summary()
    print(
        json.dumps(
            {
                "segments": rows,
                "max_error_deg": summary.max_error_deg,
                "final_error_arcsec": summary.final_error_arcsec,
                "settle_time_s": summary.settle_time_s,
                "fuel_kg": summary.fuel_kg,
                "torque_saturated_s": summary.torque_saturated_s,
            },
            indent=1,
        )
    )


if __name__ == "__main__":
    main()
