"""Benchmark of the placement MILP (HiGHS through scipy) on the paper's debris.

For each candidate grid per face (2 x 2: the paper's 24 mounts; 3 x 3: 54;
4 x 4: 96) and CubeSat count, the worst-axis, worst-single-failure and
worst-double-failure objectives: wall time, status, objective, proven bound,
gap, extensive or generated form and its size. Each solve has a time limit
(``--time-limit``); a solve that reaches it reports its gap rather than a time.

    python benchmarks/placement.py [--time-limit S] [--record] [--quick] [--out FILE]
"""

from __future__ import annotations

import time

from casadi_debris import load_problem
from casadi_debris.studies.placement import (
    OBJECTIVES,
    PlacementSettings,
    face_candidates,
    placement_data,
    solve_placement,
)
from recording import Setting, start_benchmark

FULL_CASES = [
    (2, 24, "worst-axis"), (2, 20, "worst-axis"), (2, 12, "worst-axis"),
    (2, 20, "worst-single-failure"), (2, 20, "worst-double-failure"),
    (3, 24, "worst-axis"), (3, 24, "worst-single-failure"), (3, 24, "worst-double-failure"),
    (4, 24, "worst-axis"), (4, 20, "worst-axis"), (4, 16, "worst-axis"), (4, 12, "worst-axis"),
    (4, 24, "worst-single-failure"), (4, 24, "worst-double-failure"),
]  # fmt: skip
QUICK_CASES = [(2, 24, "worst-axis"), (2, 20, "worst-single-failure"), (4, 24, "worst-axis")]


def run_case(grid: int, count: int, objective: str, time_limit_s: float) -> dict:
    problem = load_problem()
    data = placement_data(problem, face_candidates(problem, (grid, grid)))
    settings = PlacementSettings(
        (count, count), failures=OBJECTIVES[objective], time_limit_s=time_limit_s
    )
    start = time.perf_counter()
    solution = solve_placement(data, settings)
    wall = time.perf_counter() - start
    last = solution.solves[-1]
    return {
        "grid": f"{grid}x{grid}",
        "candidates": data.n_candidates,
        "count": count,
        "objective": objective,
        "time_s": wall,
        "optimal": solution.optimal,
        "worst_ratio": solution.objective,
        "upper_bound": solution.upper_bound,
        "gap": solution.gap,
        "method": solution.method,
        "rounds": len(solution.solves),
        "blocks_extensive": solution.blocks_total,
        "blocks_used": solution.blocks_used,
        "variables_last": last.variables,
        "rows_last": last.rows,
        "status_last": last.message,
    }


OPTIONS = {
    "--time-limit": Setting(600.0, 60.0, "seconds per case (600)"),
}


def main() -> None:
    args, recording, settings = start_benchmark(
        "placement",
        __doc__,
        "three cases, 60 s each at most",
        OPTIONS,
        libraries=("scipy", "highspy"),
    )
    cases = QUICK_CASES if args.quick else FULL_CASES
    results = []
    for grid, count, objective in cases:
        results.append(run_case(grid, count, objective, args.time_limit))
        print(results[-1], flush=True)
    recording.finish(settings, {"cases": results})


if __name__ == "__main__":
    main()
