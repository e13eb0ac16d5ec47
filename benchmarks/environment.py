"""Benchmark: the cost of the environment torques in the closed-loop step; prints JSON.

Usage: python benchmarks/environment.py [--repeat N] [--quick] [--record] [--out FILE]

``--record`` also writes ``docs/benchmarks/environment.json`` (see ``recording.py``).
``--quick``: 3 repeats instead of 7.

One control period of the paper's pointing loop (RK4 plant with all array
modes, star tracker, controller, saturation), rolled out over 1000 periods, on
CasADi's virtual machine and JIT-compiled to C, with

- ``none``: the paper's loop (no ``[environment]``);
- ``gravity_gradient``: the gravity gradient alone;
- ``all``: gravity gradient, aerodynamic and solar pressure on the ten faces,
  and the magnetic dipole.

``*_over_none`` are the per-step ratios; the target is at most 2.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import statistics
import time

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import ENVIRONMENT_TORQUES, default_controller_path, load_problem
from casadi_debris.model import build_model
from casadi_debris.robust.controller import ControllerRecord
from casadi_debris.simulation import build_loop_step, discretize_controller, scenario_reference
from recording import Recording, add_options, resolve

CHUNK = 1000
VARIANTS = {"none": (), "gravity_gradient": ("gravity_gradient",), "all": ENVIRONMENT_TORQUES}


def step_us(problem, record, repeat: int, jit: bool) -> tuple[float, bool]:
    """Median wall time of one period in a 1000-period roll-out [us], and whether compiled."""
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
    walls = []
    for _ in range(repeat):
        started = time.perf_counter()
        loop.roll(z0, inputs, model.nominal_parameters)
        walls.append((time.perf_counter() - started) / CHUNK)
    return statistics.median(walls) * 1e6, loop.compiled


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, help="roll-outs of each timing, median kept (7)")
    add_options(parser, "environment", "3 repeats")
    args = parser.parse_args()
    recording = Recording("environment", args)
    settings = resolve(args, full={"repeat": 7}, quick={"repeat": 3})
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    paper = load_problem("paper_pointing")
    record = ControllerRecord.from_dict(json.loads(default_controller_path().read_text()))
    report: dict = {}
    for jit in (False, True):
        label = "compiled" if jit else "virtual_machine"
        times = {}
        for name, torques in VARIANTS.items():
            environment = dataclasses.replace(paper.environment, torques=torques)
            problem = dataclasses.replace(paper, environment=environment)
            times[name], compiled = step_us(problem, record, args.repeat, jit)
            if jit and not compiled:
                times[name] = None
        report[f"step_us_{label}"] = times
        if times["none"]:
            report[f"ratio_{label}"] = {
                f"{name}_over_none": times[name] / times["none"]
                for name in VARIANTS
                if name != "none" and times[name]
            }
    report["target_ratio"] = 2.0
    recording.finish(settings, report)


if __name__ == "__main__":
    main()
