"""Benchmark: the transfer OCP (``plan_transfer``), the paper's swarm and a weak one; prints JSON.

Usage: python benchmarks/transfer.py [--problems a,b] [--repeats N] [--intervals K]
[--quick] [--record] [--out FILE]

``--record`` also writes ``docs/benchmarks/transfer.json`` (see ``recording.py``).
``--quick``: the paper only, one repeat.

Each problem is planned ``repeats`` times at minimum time; the medians of the
whole plan's wall time, the OCP's wall and its CPU time (the process's, which a
machine shared with other work inflates much less than the wall), with IPOPT's
iterations, the number of burns, arcs and shooting intervals, and the OCP's Δv
beside Edelbaum's. ``--intervals`` overrides the plan's cap on shooting
intervals (0: one interval per arc, the transcription before the arcs were
grouped), to compare the two.
"""

from __future__ import annotations

import statistics
import time

from casadi_debris import load_problem
from casadi_debris.orbit.transfer import TARGET_SEGMENTS, plan_transfer
from recording import Setting, start_benchmark

WEAK = "differential_2u"  # 0.1 mN engines, one stage: about a hundred burns


OPTIONS = {
    "--problems": Setting(
        f"paper,{WEAK}", "paper", f"comma-separated problem names (paper,{WEAK})"
    ),
    "--repeats": Setting(3, 1, "plans per problem (3)"),
    "--intervals": Setting(
        TARGET_SEGMENTS, TARGET_SEGMENTS, "most shooting intervals, 0: one per arc (28)"
    ),
}


def _cpu_s() -> float:
    return time.process_time()


def _plan(name: str, intervals: int | None) -> dict[str, float | int | bool | str]:
    problem = load_problem(name)
    start, cpu = time.perf_counter(), _cpu_s()
    plan = plan_transfer(problem, max_intervals=intervals)
    wall, cpu_used = time.perf_counter() - start, _cpu_s() - cpu
    result = plan.result
    return {
        "plan_wall_s": wall,
        "plan_cpu_s": cpu_used,
        "ocp_wall_s": result.ocp_solve_time_s,
        "ocp_iterations": result.ocp_iterations,
        "ocp_success": result.ocp_success,
        "burns": int(plan.optimal.burn[-1]) + 1,
        "arcs": len(plan.optimal.burn),
        "intervals": plan.optimal.intervals,
        "transfer_dv_m_s": result.transfer_dv_m_s,
        "edelbaum_dv_m_s": result.edelbaum_dv_m_s,
        "dv_vs_edelbaum_percent": result.dv_vs_edelbaum_percent,
        "transfer_time_days": result.transfer_time_days,
        "guidance_time_days": result.guidance_time_days,
    }


def main() -> None:
    _args, recording, settings = start_benchmark(
        "transfer", __doc__, "the paper only, one repeat", OPTIONS
    )
    intervals = settings["intervals"]
    results = {}
    for name in settings["problems"].split(","):
        runs = [_plan(name, intervals or None) for _ in range(settings["repeats"])]
        medians = {
            key: statistics.median(float(r[key]) for r in runs)
            for key in ("plan_wall_s", "plan_cpu_s", "ocp_wall_s", "ocp_iterations")
        }
        results[name] = {**runs[-1], **{f"median_{k}": v for k, v in medians.items()}}
    recording.finish(settings, {"problems": results})


if __name__ == "__main__":
    main()
