"""Benchmark: the cost of realistic sensors, estimator, delay and engines in the step; prints JSON.

Usage: python benchmarks/realism.py [--repeat N] [--quick] [--record] [--out FILE]

``--record`` also writes ``docs/benchmarks/realism.json`` (see ``recording.py``).
``--quick``: 5 repeats instead of 15.

One control period of the paper's pointing loop (RK4 plant with all array
modes, star tracker, controller, saturation), rolled out over 1000 periods, on
CasADi's virtual machine and JIT-compiled to C, with

- ``ideal``: the paper's loop (no realism table);
- ``sensors``: a noisy star tracker at 5 Hz with the MEKF and a gyro;
- ``engines``: thrust noise, misalignment, ramp, latency, minimum impulse bit
  (the step allocates thrust to the 24 engines itself);
- ``all``: both, and a computation delay.

The roll-outs are interleaved, so that the machine's other work slows them
alike; the best and the median of the repeats are kept. ``today`` is the ideal
step rolled out as before realism came in (its arrays converted to CasADi
matrices element by element, the roll-out's cost before); ``*_over_today`` are
the per-step ratios against it, the target at most 2.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import (
    Actuators,
    ControllerTiming,
    Estimation,
    Gyro,
    Sensors,
    StarTracker,
    load_problem,
)
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.simulation import Realism, StepInput, draw_noise, engine_basis
from recording import Setting, start_benchmark
from step_timing import interleaved_step_us, loop_start, loop_step, ratio_report, variant_loops

CHUNK = 1000
SENSORS = {
    "sensors": Sensors(
        star_tracker=StarTracker(noise_arcsec=5.0, update_rate_hz=5.0),
        gyro=Gyro(angle_random_walk_deg_rt_h=0.15, bias_random_walk_deg_h_rt_h=5.0),
    ),
    "estimation": Estimation(filter="mekf"),
}
ENGINES = {
    "actuators": Actuators(
        thrust_noise_fraction=0.02,
        misalignment_deg=0.5,
        ramp_time_constant_s=0.2,
        latency_s=0.05,
        minimum_impulse_bit_uNs=1.0,
    )
}
VARIANTS: dict[str, dict] = {
    "ideal": {},
    "sensors": SENSORS,
    "engines": ENGINES,
    "all": {**SENSORS, **ENGINES, "controller": ControllerTiming(delay_s=0.02)},
}


class TodayRoll:
    """The ideal step rolled out as before this change: arrays converted to CasADi matrices."""

    def __init__(self, loop) -> None:
        self.loop, self.compiled = loop, loop.compiled

    def roll(self, z, inputs, parameters):
        tiled = np.broadcast_to(parameters[:, None], (len(parameters), self.loop.chunk_steps))
        z_all, y_all = self.loop.rollout(z, inputs, tiled)
        return np.asarray(z_all), np.asarray(y_all)


def build(problem, record, jit: bool) -> tuple:
    """The compiled-or-not loop step of ``problem`` and the inputs of 1000 periods."""
    model = build_model(problem)
    reference = scenario_reference(problem)
    period = float(reference.time_s[1] - reference.time_s[0])
    allocator = Allocator.from_problem(problem, model.geometry)
    realism = Realism.of(problem, period)
    basis = engine_basis(allocator) if realism and realism.engine_level else None
    loop = loop_step(
        problem, model, record, reference, allocator, CHUNK, jit=jit, realism=realism, basis=basis
    )
    z0, step_inputs = loop_start(model, loop, reference, CHUNK)
    inputs = np.zeros((loop.n_inputs, CHUNK))
    inputs[: StepInput.SIZE] = step_inputs
    if realism is not None:
        z0 = np.concatenate([z0, realism.initial_aux(problem, reference.quaternion_BN[0])])
        noise = draw_noise(problem, model.geometry, reference.time_s[:CHUNK])
        inputs[StepInput.SIZE :] = realism.inputs.rows(problem, noise, period, 0, CHUNK)
    return loop, z0, inputs, model.nominal_parameters


OPTIONS = {
    "--repeat": Setting(15, 5, "interleaved roll-outs of each (15)"),
}


def main() -> None:
    args, recording, settings = start_benchmark("realism", __doc__, "5 repeats", OPTIONS)
    paper = load_problem("paper_pointing")
    problems = {name: dataclasses.replace(paper, **extra) for name, extra in VARIANTS.items()}
    loops = variant_loops(problems, build)
    for jit in (False, True):
        loop, *rest = loops[jit, "ideal"]
        loops[jit, "today"] = (TodayRoll(loop), *rest)
    walls = interleaved_step_us(loops, args.repeat, CHUNK)
    report = ratio_report(loops, walls, ["today", *VARIANTS], "today")
    report["target_ratio"] = 2.0
    recording.finish(settings, report)


if __name__ == "__main__":
    main()
