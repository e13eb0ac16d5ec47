"""Benchmark of ``musyn`` on the textbook problem: the distillation column.

Skogestad and Postlethwaite, *Multivariable Feedback Control*, 2nd ed., section
8.12.4 (structure {1, 1, 2} complex, grid 1e-3 .. 1e3 rad/s, 61 points, as dkpy's
example). Prints JSON: peak mu per D-K step, the final peak mu beside dkpy's
(0.1.9, three steps of order-4 D-scales: 1.0360), why the iteration stopped, and the
wall time of each step and of the whole synthesis. The design's target: 30 s or
less.

    python benchmarks/musyn_distillation.py [--out FILE] [--note TEXT]

``--quick`` is accepted for symmetry with the other scripts and runs the same.
"""

from __future__ import annotations

import time

import numpy as np

from casadi_debris.robust.examples import DISTILLATION_BLOCKS, distillation_column
from casadi_debris.robust.synthesis import musyn
from recording import Setting, start_benchmark

DKPY_MU = 1.0360
TARGETS = {"synthesis_s": 30.0}


OPTIONS = {
    "--points": Setting(61, 61, "frequency points, 1e-3 .. 1e3 rad/s (61)"),
}


def main() -> None:
    args, recording, settings = start_benchmark(
        "musyn_distillation", __doc__, "the same run", OPTIONS, libraries=("control", "slycot")
    )
    omega = np.logspace(-3, 3, args.points)
    start = time.perf_counter()
    result = musyn(distillation_column(), DISTILLATION_BLOCKS, 2, 2, omega=omega)
    synthesis_s = time.perf_counter() - start
    recording.finish(
        settings,
        {
            "synthesis_s": synthesis_s,
            "mu_peak": result.mu_peak,
            "mu_peak_dkpy": DKPY_MU,
            "mu_ratio_to_dkpy": result.mu_peak / DKPY_MU,
            "stop_reason": result.stop_reason,
            "controller_order": result.controller.nstates,
            "dk_iterations": [
                {
                    "index": it.index,
                    "d_order": it.d_order,
                    "gamma": it.gamma,
                    "mu_peak": it.mu_peak,
                    "time_s": it.time_s,
                }
                for it in result.iterations
            ],
            "targets": TARGETS,
        },
    )


if __name__ == "__main__":
    main()
