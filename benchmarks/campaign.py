"""Benchmark of whole campaigns: the paper's slew corners and its failure cases; prints JSON.

Usage: python benchmarks/campaign.py [--corners N] [--max-failed K] [--workers W]
       [--batch B] [--alone-cases N] [--baseline-src DIR] [--quick] [--record] [--out FILE]

``--record`` also writes ``docs/benchmarks/campaign.json`` (see ``recording.py``).
``--quick``: 32 corners, single failures only (24 cases), 4 cases alone.

Measured in one run, so that the ratios hold on a loaded machine:

- ``step_us``: one control period of one case inside a 1000-period roll-out:
  ``batched`` (the compiled function mapped over ``--batch`` cases, per case),
  ``compiled_alone`` (the same function with one slot, as ``simulate`` runs it with
  ``LoopSettings(jit=True)``), ``compiled_constants`` (the step compiled with the
  authority folded in, called through CasADi) and ``virtual_machine``;
- ``corners``: ``--corners`` corner cases of the paper's slew (256: the paper's
  set) on ``--workers`` processes, batched and one by one (same compiled step);
  on the virtual machine, ``--alone-cases`` of them, scaled to all;
- ``failures``: the failure campaign of the paper's swarm (every set of up to
  ``--max-failed`` failed CubeSats, 300 for 2; no lost-stage cases), the slew and
  one orbit of pointing for each on the nominal plant, 16 corners for the 3 worst,
  batched; and ``--alone-cases`` of its nominal slew and pointing runs one by one
  on the virtual machine (how the campaign ran before), scaled to all;
- with ``--baseline-src DIR`` (another checkout's ``src``, e.g. the code before a
  change): the same corner campaign, one by one compiled, with that code, on
  ``--alone-cases`` x 4 corners, scaled.

Targets: 256 corners <= 25 s on 2 cores; the 300 failure cases in closed loop
<= 180 s.
"""

from __future__ import annotations

import json
import os
import resource
import statistics
import subprocess
import sys
import time
from dataclasses import replace
from functools import partial

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.campaigns import CampaignSetup, corner_cases, nominal_case, run_campaign
from casadi_debris.config import default_problem_path, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.simulation import build_loop_step, discretize_controller
from casadi_debris.simulation._batched import FACET_CAPACITY_MIN, batched_loop
from casadi_debris.studies.failures import (
    FailureSettings,
    failure_cases,
    failure_study,
    fly_cases,
    manoeuvres,
)
from casadi_debris.workflows import (
    DEFAULT_CORNERS,
    CaseSelection,
    load_controller,
    verification_problems,
)
from recording import Setting, start_benchmark

CHUNK = 1000
REPEAT = 3
BASELINE_SCRIPT = """
import json, resource, sys, time
from casadi_debris.config import default_problem_path, load_problem
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.campaigns import CampaignSetup, corner_cases, run_campaign
from casadi_debris.workflows import load_controller
problem = load_problem(default_problem_path().parent / "paper_slew.toml")
model = build_model(problem)
setup = CampaignSetup.create(problem, load_controller(None)[0].reduced, scenario_reference(problem))
cases = corner_cases(model)[: int(sys.argv[1])]
def cpu():
    own, kids = (resource.getrusage(w) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime
started, spent = time.perf_counter(), cpu()
run_campaign(setup, cases, workers=int(sys.argv[2]))
wall, spent = time.perf_counter() - started, cpu() - spent
print(json.dumps({"wall_s": wall, "cpu_s": spent, "cases": len(cases)}))
"""


class Clock:
    """Wall time and CPU time (this process and the workers it waited for) of a block."""

    def __enter__(self) -> Clock:
        self.wall, self.cpu = time.perf_counter(), _cpu_s()
        return self

    def __exit__(self, *exc: object) -> None:
        self.wall_s = time.perf_counter() - self.wall
        self.cpu_s = _cpu_s() - self.cpu


def _cpu_s() -> float:
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def step_costs(problem, model, controller, batch: int) -> dict[str, float | None]:
    """Microseconds per control period of one case, on each path."""
    reference = scenario_reference(problem)
    discrete = discretize_controller(controller, float(reference.time_s[1] - reference.time_s[0]))
    polytope = Allocator.from_problem(problem, model.geometry).authority_polytope()
    steps = problem.simulation.integrator_steps
    z0 = np.concatenate([model.initial_state(), np.zeros(discrete.n_states)])
    inputs = np.zeros((8, CHUNK))
    inputs[0] = reference.time_s[:CHUNK]
    inputs[1:5] = reference.quaternion_BN[:CHUNK].T
    p = model.nominal_parameters

    def timed(call, cases: int) -> float:
        call()  # loads or compiles
        spent = []
        for _ in range(REPEAT):
            started = time.process_time()  # CPU time: a busy machine's preemption left out
            call()
            spent.append(time.process_time() - started)
        return statistics.median(spent) / (CHUNK * cases) * 1e6

    costs: dict[str, float | None] = {}
    for label, slots in (("batched", batch), ("compiled_alone", 1)):
        loop = batched_loop(
            model,
            discrete,
            cases=slots,
            capacity=FACET_CAPACITY_MIN,
            integrator_steps=steps,
            chunk_steps=CHUNK,
        )
        if loop is None:
            costs[label] = None
            continue
        z = np.tile(z0, (slots, 1))
        s = np.tile(inputs.T, (slots, 1, 1))
        ps = np.tile(p, (slots, 1))
        costs[label] = timed(partial(loop.roll, z, s, ps, [polytope] * slots), slots)
    for label, jit in (("compiled_constants", True), ("virtual_machine", False)):
        folded = build_loop_step(
            model, p, discrete, polytope, integrator_steps=steps, chunk_steps=CHUNK, jit=jit
        )
        costs[label] = timed(partial(folded.roll, z0, inputs, p), 1)
    return costs


def warm(problem, model, controller, sizes: tuple[int, ...]) -> float:
    """Compile (or load) the batched loops the campaigns use (compiling is once per machine:
    failure sets may need 32 facets); the seconds it took."""
    started = time.perf_counter()
    reference = scenario_reference(problem)
    discrete = discretize_controller(controller, float(reference.time_s[1] - reference.time_s[0]))
    for slots in sizes:
        for capacity in (FACET_CAPACITY_MIN, 2 * FACET_CAPACITY_MIN):
            batched_loop(
                model,
                discrete,
                cases=slots,
                capacity=capacity,
                integrator_steps=problem.simulation.integrator_steps,
                chunk_steps=CHUNK,
            )
    return time.perf_counter() - started


def corner_campaign(problem, model, controller, args) -> dict[str, float | int]:
    """Wall and CPU times of the corner campaign: batched, one by one, on the VM (scaled)."""
    reference = scenario_reference(problem)
    every = corner_cases(model)
    picks = np.unique(np.linspace(0, len(every) - 1, args.corners).round().astype(int))
    cases = [every[i] for i in picks]
    setup = CampaignSetup.create(problem, controller, reference, batch_cases=args.batch)
    result: dict[str, float | int] = {"cases": len(cases), "workers": args.workers}
    for label, chosen in (("batched", setup), ("one_by_one", replace(setup, batch_cases=1))):
        with Clock() as clock:
            run_campaign(chosen, cases, workers=args.workers)
        result[f"{label}_wall_s"], result[f"{label}_cpu_s"] = clock.wall_s, clock.cpu_s
    alone = cases[: args.alone_cases]
    with Clock() as clock:
        run_campaign(replace(setup, jit=False), alone, workers=args.workers)
    result["virtual_machine_wall_s_scaled"] = clock.wall_s * len(cases) / len(alone)
    result["virtual_machine_cpu_s_scaled"] = clock.cpu_s * len(cases) / len(alone)
    result["batched_speedup_over_one_by_one"] = result["one_by_one_cpu_s"] / result["batched_cpu_s"]
    return result


def failure_campaign(problem, model, controller, args) -> dict[str, float | int]:
    """The failure study batched; a few of its cases' nominal runs each way."""
    settings = FailureSettings(
        max_failed=args.max_failed, stages=False, workers=args.workers, batch_cases=args.batch
    )
    slew, pointing = verification_problems(problem)
    flown = manoeuvres(slew, pointing)
    corners = CaseSelection(max_cases=DEFAULT_CORNERS).cases(model)
    cases = failure_cases(len(problem.cubesats), args.max_failed, stages=False)
    cases = cases[: args.failure_cases]
    with Clock() as study_clock:
        study = failure_study(
            model,
            settings,
            controller=controller,
            manoeuvres=flown,
            corner_plants=corners,
            cases=cases,
        )
    alone = cases[:: max(1, len(cases) // args.alone_cases)][: args.alone_cases]
    plants = [nominal_case(model)]
    subset: dict[str, float] = {}
    for label, jit in (("batched", True), ("virtual_machine", False)):
        with Clock() as clock:
            for manoeuvre in flown:
                fly_cases(
                    manoeuvre,
                    controller,
                    alone,
                    plants,
                    workers=args.workers,
                    jit=jit,
                    batch_cases=args.batch,
                )
        subset[f"{label}_wall_s"], subset[f"{label}_cpu_s"] = clock.wall_s, clock.cpu_s
    return {
        "cases": len(cases),
        "nominal_runs": (len(cases) + 1) * len(flown),
        "corner_runs": study.corner_plants * settings.corner_sets * len(flown),
        "workers": args.workers,
        "batched_wall_s": study_clock.wall_s,
        "batched_cpu_s": study_clock.cpu_s,
        "cases_met": sum(r.met is True for r in study.cases),
        "subset_cases": len(alone),
        "subset": subset,
        "subset_speedup_cpu": subset["virtual_machine_cpu_s"] / subset["batched_cpu_s"],
    }


def baseline(src: str, cases: int, workers: int) -> dict[str, float]:
    """The corner campaign, one by one, with the code in ``src`` (a fresh process)."""
    environment = {**os.environ, "PYTHONPATH": src}
    done = subprocess.run(
        [sys.executable, "-c", BASELINE_SCRIPT, str(cases), str(workers)],
        capture_output=True,
        text=True,
        env=environment,
        check=True,
    )
    answer = json.loads(done.stdout.strip().splitlines()[-1])
    return {"src": src, **answer}


OPTIONS = {
    "--corners": Setting(256, 32, "corner cases (256)"),
    "--max-failed": Setting(2, 1, "largest failed set (2: 300 cases)"),
    "--workers": {"type": int, "default": 2},
    "--batch": {"type": int, "default": 16, "help": "cases per compiled call"},
    "--alone-cases": Setting(8, 4, "cases timed on the VM (8)"),
    "--failure-cases": {
        "type": int,
        "help": "keep the first N failure cases (a smoke test)",
    },
    "--baseline-src": {"help": "another checkout's src to time the corners with"},
}


def main() -> None:
    args, recording, settings = start_benchmark(
        "campaign", __doc__, "32 corners, single failures (24 cases), 4 cases alone", OPTIONS
    )
    settings |= {"workers": args.workers, "batch": args.batch}
    problem = load_problem(default_problem_path().parent / "paper_slew.toml")
    model = build_model(problem)
    controller = load_controller(None)[0].reduced
    warm_s = warm(problem, model, controller, tuple(sorted({1, 2, 4, 8, 16, args.batch})))
    report = {
        "warm_s": warm_s,
        "step_cpu_us": step_costs(problem, model, controller, args.batch),
        "corners": corner_campaign(problem, model, controller, args),
        "failures": failure_campaign(problem, model, controller, args),
        "targets": {"corners_256_wall_s_2_cores": 25.0, "failures_300_wall_s": 180.0},
    }
    if args.baseline_src:
        measured = baseline(args.baseline_src, 4 * args.alone_cases, args.workers)
        scale = report["corners"]["cases"] / measured["cases"]
        report["baseline"] = {
            **measured,
            "corners_wall_s_scaled": measured["wall_s"] * scale,
            "corners_cpu_s_scaled": measured["cpu_s"] * scale,
        }
    recording.finish(settings, report)


if __name__ == "__main__":
    main()
