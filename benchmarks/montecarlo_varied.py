"""Benchmark: what a case of ``[[montecarlo.vary]]`` costs; prints JSON.

Usage: python benchmarks/montecarlo_varied.py [--repeat N] [--quick] [--record] [--out FILE]

``--record`` also writes ``docs/benchmarks/montecarlo_varied.json`` (see ``recording.py``).
``--quick``: the paper's slew cut to 300 s and 2 repeats, instead of the whole 1500 s and 3.

One case of the paper's slew (1500 s at 10 Hz), in one process, as a campaign's
worker runs it (``run_case``):

- ``parameter``: a case that varies a model parameter (``mass_kg``): the
  worker's step, compiled to C once (its compile is done before timing), takes
  the case's parameter vector;
- ``file_key``: a case that varies a key of the problem file
  (``disturbance.amplitude_mNm[2]``): the problem is read again, the model built
  again, and the case runs on CasADi's virtual machine (compiling a step for
  one case would cost more than it saves);
- ``rebuild``: reading the problem again and building its model alone.

The best and the median of the repeats are kept.
"""

from __future__ import annotations

import os
import statistics
import time

import numpy as np

from casadi_debris.campaigns import CampaignSetup, Case, CaseRunner
from casadi_debris.config import load_problem, problem_with_values, with_duration
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.workflows import controller_for
from recording import Setting, start_benchmark


def _case(model, name: str, value: float, parameters: np.ndarray) -> Case:
    zero = np.zeros(model.parameter_layout.size)
    return Case(f"bench-{name}", "varied", 0, 0, zero, parameters, varied=((name, value),))


OPTIONS = {
    "--repeat": Setting(3, 2, "cases of each kind (3)"),
    "--duration-s": Setting(1500.0, 300.0, "length of the slew run (1500)"),
}


def main() -> None:
    args, recording, settings = start_benchmark(
        "montecarlo_varied", __doc__, "300 s runs, 2 repeats", OPTIONS
    )
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    problem = with_duration(load_problem("paper_slew"), args.duration_s)
    record, _ = controller_for(problem, None)
    setup = CampaignSetup.create(problem, record.reduced, scenario_reference(problem), jit=True)
    runner = CaseRunner(setup)
    mass = runner.model.nominal.replace(mass_kg=700.0).to_vector()
    cases = {
        "parameter": _case(runner.model, "mass_kg", 700.0, mass),
        "file_key": _case(
            runner.model, "disturbance.amplitude_mNm[2]", 1.0, runner.model.nominal_parameters
        ),
    }
    runner(cases["parameter"])  # the worker's one compile, before timing
    walls: dict[str, list[float]] = {"parameter": [], "file_key": [], "rebuild": []}
    compiled = None
    for _ in range(args.repeat):
        for name, case in cases.items():
            started = time.perf_counter()
            outcome = runner(case)
            walls[name].append(time.perf_counter() - started)
            if name == "parameter":
                compiled = outcome.summary.run.compiled_step
        started = time.perf_counter()
        build_model(problem_with_values(problem, cases["file_key"].varied))
        walls["rebuild"].append(time.perf_counter() - started)
    report: dict = {"parameter_case_compiled": compiled}
    for kind, pick in (("best", min), ("median", statistics.median)):
        report[f"case_s_{kind}"] = {name: pick(times) for name, times in walls.items()}
    best = report["case_s_best"]
    report["file_key_over_parameter_best"] = best["file_key"] / best["parameter"]
    recording.finish(settings, report)


if __name__ == "__main__":
    main()
