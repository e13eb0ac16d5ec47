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

import argparse
import dataclasses
import json
import os

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import ENVIRONMENT_TORQUES, default_controller_path, load_problem
from casadi_debris.model import build_model
from casadi_debris.robust.controller import ControllerRecord
from casadi_debris.simulation import build_loop_step, discretize_controller, scenario_reference
from recording import Recording, add_options, resolve
from step_timing import interleaved_step_us, ratio_report

CHUNK = 1000
VARIANTS = {"none": (), "gravity_gradient": ("gravity_gradient",), "all": ENVIRONMENT_TORQUES}


def build(problem, record, jit: bool) -> tuple:
    """The compiled-or-not loop step of ``problem`` and the inputs of 1000 periods."""
    model = build_model(problem)
    reference = scenario_reference(problem)
    period = float(reference.time_s[1] - reference.time_s[0])
    allocator = Allocator.from_problem(problem, model.geometry)
    loop = build_loop_step(
        model,
        model.nominal_parameters,
        discretize_controller(record.reduced, period),
        allocator.authority_polytope(),
        integrator_steps=problem.simulation.integrator_steps,
        chunk_steps=CHUNK,
        jit=jit,
    )
    z0 = np.concatenate([model.initial_state(), np.zeros(loop.n_controller)])
    inputs = np.vstack(
        [reference.time_s[:CHUNK], reference.quaternion_BN[:CHUNK].T, np.zeros((3, CHUNK))]
    )
    return loop, z0, inputs, model.nominal_parameters


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, help="interleaved roll-outs of each (15)")
    add_options(parser, "environment", "5 repeats")
    args = parser.parse_args()
    recording = Recording("environment", args)
    settings = resolve(args, full={"repeat": 15}, quick={"repeat": 5})
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    paper = load_problem("paper_pointing")
    record = ControllerRecord.from_dict(json.loads(default_controller_path().read_text()))
    loops = {}
    for jit in (False, True):
        for name, torques in VARIANTS.items():
            environment = dataclasses.replace(paper.environment, torques=torques)
            problem = dataclasses.replace(paper, environment=environment)
            loops[jit, name] = build(problem, record, jit)
    walls = interleaved_step_us(loops, args.repeat, CHUNK)
    report = ratio_report(loops, walls, VARIANTS, "none")
    report["target_ratio"] = 2.0
    recording.finish(settings, report)


if __name__ == "__main__":
    main()
