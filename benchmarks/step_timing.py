"""Per-step timing of closed-loop steps, interleaved so that other load hits all alike.

Shared by the benchmarks that compare variants of the compiled step
(``environment.py``, ``realism.py``).
"""

from __future__ import annotations

import statistics
import time


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
