"""Benchmark of ``mu_bounds`` on the paper's closed loop: both bounds on 200 frequencies.

The shipped controller (full and reduced order) closed around the paper's design
plant, 1e-4 .. 1e2 rad/s, with the design's structure (a 3 x 3 full complex
uncertainty block and a 6 x 6 performance block). Prints JSON: per controller the
peak upper and lower bounds, their gap, the frequency of the peak and the wall time
(median of ``--repeats``). The design's target: 20 s or less for 200 frequencies.

    python benchmarks/mu_bounds.py [--points N] [--repeats R] [--out FILE] [--note TEXT]
"""

from __future__ import annotations

import statistics
import time

import numpy as np

from casadi_debris import load_problem
from casadi_debris.dynamics import build_model, linearize
from casadi_debris.robust import mu_bounds
from casadi_debris.robust.plant import (
    frequency_response,
    generalized_plant,
    recorded_performance_weights,
    weight_system,
)
from casadi_debris.workflows import load_controller
from recording import Setting, start_benchmark

TARGETS = {"mu_bounds_200_s": 20.0}
BLOCKS = [("complex", 3), ("complex", 6)]


def paper_responses(omega: np.ndarray) -> dict[str, np.ndarray]:
    """Closed-loop responses of the shipped controllers on the paper's design plant."""
    problem = load_problem()
    record, _ = load_controller()
    coefficients = np.array(
        record.details["uncertainty_weight"]["coefficients_k_wz_zetaz_wp_zetap"]
    )
    model = build_model(problem, modes=record.details.get("design_plant_modes", "first"))
    plant = generalized_plant(
        linearize(model, sensor=True, units="deg_mNm"),
        weight_system(coefficients),
        recorded_performance_weights(problem, record.details.get("weights", {})),
    )
    controllers = {"reduced": record.reduced}
    if record.full is not None:
        controllers["full"] = record.full
    return {
        name: frequency_response(plant.system.lft(k, 3, 3), omega)
        for name, k in controllers.items()
    }


OPTIONS = {
    "--points": Setting(200, 200, "frequencies, 1e-4 .. 1e2 rad/s (200)"),
    "--repeats": Setting(3, 1, "timed runs per controller (3)"),
}


def main() -> None:
    args, recording, settings = start_benchmark(
        "mu_bounds", __doc__, "one run per controller", OPTIONS, libraries=("control", "slycot")
    )
    omega = np.logspace(-4, 2, args.points)
    results = {}
    for name, responses in paper_responses(omega).items():
        times = []
        for _ in range(args.repeats):
            start = time.perf_counter()
            bounds = mu_bounds(responses, BLOCKS)
            times.append(time.perf_counter() - start)
        k = bounds.peak_index
        results[name] = {
            "peak_upper": bounds.peak_upper,
            "peak_lower": bounds.peak_lower,
            "gap": bounds.gap,
            "peak_rad_s": float(omega[k]),
            "lower_at_peak": float(bounds.lower[k]),
            "upper_method": bounds.upper_method,
            "time_s_median": statistics.median(times),
            "time_s": times,
        }
    recording.finish(settings, {"blocks": BLOCKS, "controllers": results, "targets": TARGETS})


if __name__ == "__main__":
    main()
