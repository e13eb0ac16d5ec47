"""Benchmark: the cost of the environment torques in the closed-loop step; prints JSON.

Usage: python benchmarks/environment.py [--repeat N] [--quick] [--record] [--out FILE]

``--record`` also writes ``docs/benchmarks/environment.json`` (see ``recording.py``).
``--quick``: 5 repeats instead of 15.

One control period of the paper's pointing loop (RK4 plant with all array
modes, star tracker, controller, saturation), rolled out over 1000 periods, on
CasADi's virtual machine and JIT-compiled to C, with

- ``none``: the paper's loop (no ``[environment]``);
- ``gravity_gradient``: the gravity gradient alone;
- ``all``: gravity gradient, aerodynamic and solar pressure on the ten faces,
  and the magnetic dipole.

The roll-outs of the six steps are interleaved, so that the machine's other
work slows them alike; the best and the median of the repeats are kept.
``*_over_none`` are the per-step ratios; the target is at most 2.
"""

from __future__ import annotations

import dataclasses

from casadi_debris.allocation import Allocator
from casadi_debris.config import ENVIRONMENT_TORQUES, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from recording import Setting, start_benchmark
from step_timing import interleaved_step_us, loop_start, loop_step, ratio_report, variant_loops

CHUNK = 1000
VARIANTS = {"none": (), "gravity_gradient": ("gravity_gradient",), "all": ENVIRONMENT_TORQUES}


def build(problem, record, jit: bool) -> tuple:
    """The compiled-or-not loop step of ``problem`` and the inputs of 1000 periods."""
    model = build_model(problem)
    reference = scenario_reference(problem)
    allocator = Allocator.from_problem(problem, model.geometry)
    loop = loop_step(problem, model, record, reference, allocator, CHUNK, jit=jit)
    return loop, *loop_start(model, loop, reference, CHUNK), model.nominal_parameters


OPTIONS = {
    "--repeat": Setting(15, 5, "interleaved roll-outs of each (15)"),
}


def main() -> None:
    args, recording, settings = start_benchmark("environment", __doc__, "5 repeats", OPTIONS)
    paper = load_problem("paper_pointing")
    problems = {
        name: dataclasses.replace(
            paper, environment=dataclasses.replace(paper.environment, torques=torques)
        )
        for name, torques in VARIANTS.items()
    }
    loops = variant_loops(problems, build)
    walls = interleaved_step_us(loops, args.repeat, CHUNK)
    report = ratio_report(loops, walls, VARIANTS, "none")
    report["target_ratio"] = 2.0
    recording.finish(settings, report)


if __name__ == "__main__":
    main()
