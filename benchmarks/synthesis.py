"""Benchmark of the robust design: D-K iteration and the 3000-sample margin sweep.

Prints JSON: wall time of each D-K step, of the whole synthesis and of the
margin sweep with 1 and 2 worker processes (their ratio measured in the same run).
Targets (issue 3): synthesis <= 60 s, margin sweep <= 30 s on 2 cores.

    python benchmarks/synthesis.py [--samples 3000]
"""

from __future__ import annotations

import argparse
import json
import os
import time

from casadi_debris import load_problem
from casadi_debris.robust.analysis import margin_study
from casadi_debris.robust.design import design_controller


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--samples", type=int, default=3000)
    args = parser.parse_args()
    problem = load_problem()
    steps = []
    start = time.perf_counter()
    design = design_controller(
        problem, progress=lambda stage, it: steps.append((stage, it, time.perf_counter() - start))
    )
    synthesis_s = time.perf_counter() - start
    sweeps = {}
    for workers in (1, 2):
        begin = time.perf_counter()
        study = margin_study(problem, design.record.reduced, args.samples, workers=workers)
        sweeps[workers] = (time.perf_counter() - begin, study.sampled_min())
    print(
        json.dumps(
            {
                "cpu_count": os.cpu_count(),
                "synthesis_s": synthesis_s,
                "stage_times_s": design.timings_s,
                "dk_iterations": [
                    {
                        "index": it.index,
                        "d_order": it.d_order,
                        "mu_peak": it.mu_peak,
                        "time_s": it.time_s,
                    }
                    for stage, it, _ in steps
                    if it is not None
                ],
                "mu_peak": design.summary()["mu_peak"],
                "mu_peak_reduced": design.summary()["mu_peak_reduced"],
                "margin_sweep_samples": args.samples,
                "margin_sweep_s_1_worker": sweeps[1][0],
                "margin_sweep_s_2_workers": sweeps[2][0],
                "margin_sweep_speedup": sweeps[1][0] / sweeps[2][0],
                "sampled_min": sweeps[2][1],
            },
            indent=1,
        )
    )


if __name__ == "__main__":
    main()
