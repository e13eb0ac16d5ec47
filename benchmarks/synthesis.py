"""Benchmark of the robust design: D-K iteration and the 3000-sample margin sweep.

Prints JSON: wall time of each D-K step, of the whole synthesis and of the
margin sweep with 1 and 2 worker processes (their ratio measured in the same run),
with the load average before each sweep (the machine may be busy with other work).
The design's targets: synthesis <= 60 s, margin sweep <= 30 s on 2 cores.

    python benchmarks/synthesis.py [--samples 3000] [--sweep-only] [--quick] [--record]
        [--out FILE] [--note TEXT]

``--sweep-only`` skips the synthesis and sweeps the shipped controller.
``--record`` also writes ``docs/benchmarks/synthesis.json`` (see ``recording.py``).
``--quick``: a 300-sample sweep (default: 3000); the synthesis is the same.
"""

from __future__ import annotations

import json
import os
import time

import control

from casadi_debris import load_problem
from casadi_debris.config import Problem, default_controller_path
from casadi_debris.robust.margins import margin_study
from casadi_debris.robust.plant import Controller
from casadi_debris.robust.synthesis import design_controller
from recording import Setting, start_benchmark

TARGETS = {"synthesis_s": 60.0, "margin_sweep_s_2_workers": 30.0}  # the design's, on 2 cores


def margin_sweeps(problem: Problem, controller: control.StateSpace, samples: int) -> dict:
    """Wall time, load average before, and worst margins of the sweep with 1 and 2 workers."""
    sweeps = {}
    for workers in (1, 2):
        load = os.getloadavg()[0]
        begin = time.perf_counter()
        study = margin_study(problem, controller, samples, workers=workers)
        sweeps[workers] = (time.perf_counter() - begin, load, study.sampled_min())
    return {
        "margin_sweep_samples": samples,
        "margin_sweep_s_1_worker": sweeps[1][0],
        "margin_sweep_s_2_workers": sweeps[2][0],
        "margin_sweep_speedup": sweeps[1][0] / sweeps[2][0],
        "load_average_1min_before_1_worker": sweeps[1][1],
        "load_average_1min_before_2_workers": sweeps[2][1],
        "sampled_min": sweeps[2][2],
        "sampled_min_workers_agree": sweeps[1][2] == sweeps[2][2],
    }


OPTIONS = {
    "--samples": Setting(3000, 300, "plants of the margin sweep (3000)"),
    "--sweep-only": {"action": "store_true", "help": "sweep the shipped controller"},
}


def main() -> None:
    args, recording, settings = start_benchmark(
        "synthesis", __doc__, "a 300-sample sweep", OPTIONS, libraries=("control", "slycot")
    )
    settings["sweep_only"] = args.sweep_only
    problem = load_problem()
    if args.sweep_only:
        record = Controller.from_dict(json.loads(default_controller_path().read_text()))
        sweeps = margin_sweeps(problem, record.reduced, args.samples)
        recording.finish(settings, {**sweeps, "targets": TARGETS})
        return
    steps = []
    start = time.perf_counter()
    design = design_controller(
        problem, progress=lambda stage, it: steps.append((stage, it, time.perf_counter() - start))
    )
    synthesis_s = time.perf_counter() - start
    sweeps = margin_sweeps(problem, design.record.reduced, args.samples)
    recording.finish(
        settings,
        {
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
            "mu_peak": design.summary().mu_peak,
            "mu_peak_reduced": design.summary().mu_peak_reduced,
            **sweeps,
            "targets": TARGETS,
        },
    )


if __name__ == "__main__":
    main()
