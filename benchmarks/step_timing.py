"""Per-step timing of closed-loop steps, interleaved so that other load hits all alike.

Shared by the benchmarks that time the compiled step (``environment.py``,
``realism.py``, ``simulation.py``).
"""

from __future__ import annotations

import json
import os
import statistics
import time

import numpy as np

from casadi_debris.config import default_controller_path
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import build_loop_step, discretize_controller


def variant_loops(problems: dict, build) -> dict:
    """``build(problem, record, jit)`` of every variant flying the shipped controller, on
    CasADi's virtual machine and compiled, keyed by ``(jit, name)``; one thread each."""
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    record = Controller.from_dict(json.loads(default_controller_path().read_text()))
    return {
        (jit, name): build(problem, record, jit)
        for jit in (False, True)
        for name, problem in problems.items()
    }


def loop_step(problem, model, record, reference, allocator, chunk: int, **options):
    """The closed-loop step of ``problem`` flying ``record``'s controller at the reference's
    period, rolled out ``chunk`` periods at a time; ``options`` go to ``build_loop_step``
    (``jit``, ``realism``, ``basis``)."""
    period = float(reference.time_s[1] - reference.time_s[0])
    return build_loop_step(
        model,
        model.nominal_parameters,
        discretize_controller(record.reduced, period),
        allocator.authority_polytope(),
        integrator_steps=problem.simulation.integrator_steps,
        chunk_steps=chunk,
        **options,
    )


def loop_start(model, loop, reference, chunk: int) -> tuple[np.ndarray, np.ndarray]:
    """The initial state of ``loop`` (plant at rest, controller zero) and the inputs of
    its first ``chunk`` periods: time, reference quaternion, zero feed-forward."""
    z0 = np.concatenate([model.initial_state(), np.zeros(loop.n_controller)])
    inputs = np.vstack(
        [reference.time_s[:chunk], reference.quaternion_BN[:chunk].T, np.zeros((3, chunk))]
    )
    return z0, inputs


def interleaved_step_us(loops: dict, repeat: int, chunk: int) -> dict:
    """Microseconds per step of each ``(loop, z0, inputs, p)``, one list per key."""
    walls: dict = {key: [] for key in loops}
    for _ in range(repeat):  # interleaved: the machine's other load hits all alike
        for key, (loop, z0, inputs, p) in loops.items():
            started = time.perf_counter()
            loop.roll(z0, inputs, p)
            walls[key].append((time.perf_counter() - started) / chunk * 1e6)
    return walls


def ratio_report(loops: dict, walls: dict, variants, base: str) -> dict:
    """Best and median per step of every variant, and their ratios to ``base``.

    ``loops`` and ``walls`` are keyed by ``(jit, variant)``.
    """
    report: dict = {}
    for jit in (False, True):
        label = "compiled" if jit else "virtual_machine"
        if jit and not loops[jit, base][0].compiled:
            report[f"step_us_{label}"] = None
            continue
        for kind, pick in (("best", min), ("median", statistics.median)):
            times = {name: pick(walls[jit, name]) for name in variants}
            report[f"step_us_{label}_{kind}"] = times
            report[f"ratio_{label}_{kind}"] = {
                f"{name}_over_{base}": times[name] / times[base]
                for name in variants
                if name != base
            }
    return report
