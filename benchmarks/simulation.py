"""Benchmark of the closed-loop simulation and the corner Monte Carlo; prints JSON.

Usage: python benchmarks/simulation.py [--repeat N] [--corners N] [--workers 1,2]
       [--scipy-s S] [--quick] [--record] [--out FILE] [--note TEXT]

``--record`` also writes ``docs/benchmarks/simulation.json`` (see ``recording.py``).
``--quick``: 1 repeat, 16 corners, 5 s of the scipy loop (default: 3, 256 and 20).

Measured in one run (ratios are what to compare across machines):

- ``step_us``: one control period (RK4 plant with all array modes, star
  tracker, controller, saturation) inside the roll-out on CasADi's virtual
  machine, and ``step_us_compiled`` JIT-compiled to C (``compile_s`` once per
  machine, into an empty cache; ``compile_warm_s`` for each later process, which
  loads the library from the cache);
- ``closed_loop_step_us``: the whole paper slew (roll-out, allocator with
  staging and fuel tracking, bookkeeping) per step, and its real-time factor;
- ``scipy_step_us``: the same loop written plainly -- a Python loop over the
  periods calling ``scipy.integrate.solve_ivp`` (RK45, the model's dynamics
  Function as right-hand side), numpy controller, ``Allocator.allocate`` per
  step -- over the first ``--scipy-s`` seconds;
- ``montecarlo_wall_s``: ``--corners`` corner cases of the slew with 1 and
  2 workers (256 = the paper's set), virtual machine and compiled.

The design's targets: <= 40 us per closed-loop step; 256 corners <= 90 s on
2 cores.
"""

from __future__ import annotations

import json
import os
import statistics
import tempfile
import time

import numpy as np
from scipy.integrate import solve_ivp

from casadi_debris.allocation import Allocator
from casadi_debris.campaigns import CampaignSetup, corner_cases, run_campaign
from casadi_debris.config import default_controller_path, default_problem_path, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import (
    LoopSettings,
    discretize_controller,
    release_compiled_steps,
    simulate_closed_loop,
)
from casadi_debris.simulation import _jit_cache as jit_cache
from casadi_debris.units import DEG_PER_RAD
from recording import Setting, start_benchmark
from step_timing import loop_start, loop_step


def scipy_loop(problem, model, controller, reference, seconds: float) -> float:
    """Seconds per step of the plain Python/scipy closed loop over ``seconds``."""
    period = float(reference.time_s[1] - reference.time_s[0])
    discrete = discretize_controller(controller, period)
    allocator = Allocator.from_problem(problem, model.geometry)
    p = model.nominal_parameters
    x = model.initial_state()
    xc = np.zeros(discrete.n_states)
    steps = int(seconds / period)
    started = time.perf_counter()
    for k in range(steps):
        t = reference.time_s[k]
        error = np.asarray(model.attitude_error(reference.quaternion_BN[k], x[model.layout.q_st]))
        command = -DEG_PER_RAD * error.ravel()
        demand = 1e-3 * (discrete.C @ xc + discrete.D @ command)
        xc = discrete.A @ xc + discrete.B @ command
        result = allocator.allocate(demand)
        wrench = (result.torque_Nm, result.force_N)

        def rate(time_s, state, wrench=wrench):
            disturbance = np.asarray(model.disturbance(time_s)).ravel()
            u = np.concatenate([wrench[0], disturbance, wrench[1]])
            return np.asarray(model.dynamics(state, u, p)).ravel()

        x = solve_ivp(rate, (t, t + period), x, rtol=1e-8, atol=1e-10).y[:, -1]
    return (time.perf_counter() - started) / steps


OPTIONS = {
    "--repeat": Setting(3, 1, "runs of each timing, median kept (3)"),
    "--corners": Setting(256, 16, "corner cases of the Monte Carlo (256)"),
    "--workers": {"default": "1,2"},
    "--scipy-s": Setting(20.0, 5.0, "seconds of the scipy loop (20)"),
}


def main() -> None:
    args, recording, settings = start_benchmark(
        "simulation", __doc__, "1 repeat, 16 corners, 5 s of the scipy loop", OPTIONS
    )
    settings["workers"] = args.workers
    os.environ.setdefault("OMP_NUM_THREADS", "1")

    problem = load_problem(default_problem_path().parent / "paper_slew.toml")
    model = build_model(problem)
    record = Controller.from_dict(json.loads(default_controller_path().read_text()))
    reference = scenario_reference(problem)
    allocator = Allocator.from_problem(problem, model.geometry)

    loop = loop_step(problem, model, record, reference, allocator, 1000)
    z0, inputs = loop_start(model, loop, reference, 1000)
    p = model.nominal_parameters

    def per_step(step_loop) -> float:
        walls = []
        for _ in range(args.repeat):
            started = time.perf_counter()
            step_loop.roll(z0, inputs, p)
            walls.append((time.perf_counter() - started) / 1000)
        return statistics.median(walls)

    step_vm = per_step(loop)

    def build_compiled():
        started = time.perf_counter()
        built = loop_step(problem, model, record, reference, allocator, 1000, jit=True)
        return built, time.perf_counter() - started

    previous_cache = os.environ.get(jit_cache.CACHE_ENV)
    with tempfile.TemporaryDirectory(ignore_cleanup_errors=True) as empty_cache:
        os.environ[jit_cache.CACHE_ENV] = empty_cache
        compiled, compile_s = build_compiled()
        release_compiled_steps()  # the next build loads the library, as a new process does
        compiled, compile_warm_s = build_compiled()
    if previous_cache is None:
        os.environ.pop(jit_cache.CACHE_ENV)
    else:
        os.environ[jit_cache.CACHE_ENV] = previous_cache
    step_c = per_step(compiled) if compiled.compiled else None

    whole = []
    for _ in range(args.repeat):
        result = simulate_closed_loop(model, record.reduced, reference, allocator=allocator)
        whole.append(result.wall_time_s)
    steps = len(result.scale)
    whole_c = []
    for _ in range(args.repeat):
        result_c = simulate_closed_loop(
            model, record.reduced, reference, allocator=allocator, settings=LoopSettings(jit=True)
        )
        whole_c.append(result_c.wall_time_s)
    scipy_s = scipy_loop(problem, model, record.reduced, reference, args.scipy_s)

    cases = corner_cases(model)
    picks = np.unique(np.linspace(0, len(cases) - 1, args.corners).round().astype(int))
    chosen = [cases[i] for i in picks]
    campaign = {}
    for jit in (False, True):
        setup = CampaignSetup.create(problem, record.reduced, reference, jit=jit)
        for workers in (int(w) for w in args.workers.split(",")):
            started = time.perf_counter()
            run_campaign(setup, chosen, workers=workers)
            label = f"{'compiled' if jit else 'virtual_machine'}_{workers}_workers"
            campaign[label] = time.perf_counter() - started

    closed_us = statistics.median(whole) / steps * 1e6
    closed_c_us = statistics.median(whole_c) / steps * 1e6
    report = {
        "steps_paper_slew": steps,
        "step_us": step_vm * 1e6,
        "step_us_compiled": None if step_c is None else step_c * 1e6,
        "compile_s": compile_s if compiled.compiled else None,
        "compile_warm_s": compile_warm_s if compiled.compiled else None,
        "closed_loop_step_us": closed_us,
        "closed_loop_step_us_compiled": closed_c_us,
        "real_time_factor_paper_slew": float(reference.time_s[-1]) / statistics.median(whole),
        "real_time_factor_paper_slew_compiled": float(reference.time_s[-1])
        / statistics.median(whole_c),
        "scipy_step_us": scipy_s * 1e6,
        "scipy_over_casadi": scipy_s * 1e6 / closed_us,
        "montecarlo_cases": len(chosen),
        "montecarlo_wall_s": campaign,
        "targets": {"closed_loop_step_us": 40.0, "montecarlo_256_wall_s_2_cores": 90.0},
    }
    recording.finish(settings, report)


if __name__ == "__main__":
    main()
