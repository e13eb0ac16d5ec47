"""Allocation benchmark: time per call per back-end, batch throughput, saturation quality.

Prints JSON (``--record``: also to ``docs/benchmarks/allocation.json``, see
``recording.py``). Not a test: numbers depend on the machine and its load.

- ``per_call``: median and p99 wall time of one ``Allocator.allocate`` call
  (Python included, as a user sees it) and of the back-end alone, for
  feasible demands and for saturating ones, per installed back-end; and the
  ratio of the median to the clipped pseudo-inverse.
- ``batch``: solves per second of ``allocate_batch`` over a mixed sequence.
- ``saturation``: on saturating demands, the fraction of the LP maximum
  torque (HiGHS, largest alpha along the demand) each method reaches, and
  the largest angle between achieved and demanded torque.
- ``tiny``: ``allocate`` on demands from 1e-300 to 1e-4 N m (log-uniform,
  random directions; solved scaled up by a power of two) and on subnormal ones
  (5e-324 to 2e-308 N m): median time, the largest relative torque error
  ``|B f - tau|_inf / |tau|_inf`` of the normal ones, the largest error of the
  subnormal ones in units of the promised floor ``n (l + 2) 2**-1074`` N m,
  and how many answers needed the HiGHS fallback.
- ``series``: ``allocate_series`` on a smooth torque history (three sines at
  0.8 of the axis authorities, about half the steps saturated) against a
  loop of ``allocate`` calls over the same history, per step, in the same
  run; each series run starts from a fresh allocator (no remembered active
  sets), its authority polytope built beforehand and timed on its own.
- ``engines_scaling``: ``allocate`` (DAQP) with the paper's 24 engines and with 48
  (eight CubeSats on a grid on each face), medians and their ratio in one run.

Usage: python benchmarks/allocation.py [--calls N] [--solvers daqp,osqp] [--series-steps K]
       [--series-repeats R] [--quick] [--record] [--out FILE] [--note TEXT]

``--quick``: 300 demands per back-end and case, a 2000-step history, 3 series runs
(default: 2000, 12,000 and 5).
"""

from __future__ import annotations

import math
import time
import tomllib

import numpy as np
from scipy.optimize import linprog

from casadi_debris import load_problem
from casadi_debris.allocation import Allocator, PseudoInverseAllocator, available_solvers
from casadi_debris.config import default_problem_path, problem_from_dict
from casadi_debris.geometry import build_geometry
from casadi_debris.units import MN_PER_N, US_PER_S
from recording import Setting, start_benchmark

SEED = 20240404


def percentiles_us(samples_s: list[float]) -> dict[str, float]:
    values = np.array(samples_s) * US_PER_S
    return {
        "median_us": float(np.median(values)),
        "p99_us": float(np.percentile(values, 99)),
    }


def demands(rng: np.random.Generator, count: int, authority_Nm: float, factor: float) -> np.ndarray:
    """Random torque demands: direction uniform on the sphere, size factor x authority scale."""
    directions = rng.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return directions * authority_Nm * factor * rng.uniform(0.2, 1.0, size=(count, 1))


def time_calls(allocate, torques: np.ndarray) -> tuple[list[float], list[float]]:
    wall, backend = [], []
    for torque in torques:
        start = time.perf_counter()
        result = allocate(torque)
        wall.append(time.perf_counter() - start)
        backend.append(result.solve_time_s)
    return wall, backend


def lp_largest_torque(geometry, limits_N: np.ndarray, torque_Nm: np.ndarray) -> float:
    """|alpha_max * demand| [N m] along the demand, zero net force (HiGHS, in mN)."""
    rows = np.vstack([geometry.torque_map, geometry.force_map])
    target = np.concatenate([torque_Nm, np.zeros(3)]) * MN_PER_N
    n = len(limits_N)
    result = linprog(
        np.append(np.zeros(n), -1.0),
        A_eq=np.hstack([rows, -target[:, None]]),
        b_eq=np.zeros(6),
        bounds=[*zip(np.zeros(n), limits_N * MN_PER_N, strict=True), (0.0, 1.0)],
        method="highs",
    )
    return float(result.x[-1]) * float(np.linalg.norm(torque_Nm))


def smooth_history(authority: dict[str, float], steps: int) -> np.ndarray:
    """tau_j(t) = 0.8 peak_j sin(2 pi c_j t + phi_j), t in [0, 1] [N m]; peak: +axis authority."""
    peak = np.array([authority["+x"], authority["+y"], authority["+z"]])
    t = np.linspace(0.0, 1.0, steps)[:, None]
    cycles = np.array([3.0, 2.0, 1.5])
    phase_rad = np.array([0.0, 0.7, 1.77])
    return 0.8 * peak * np.sin(2.0 * np.pi * cycles * t + phase_rad)


def tiny_benchmark(problem, geometry, rng: np.random.Generator, count: int) -> dict:
    """Tiny demands: time, worst relative error (normal floats), worst error (subnormals)."""
    allocator = Allocator.from_problem(problem, geometry)
    directions = rng.normal(size=(2 * count, 3))
    directions /= np.abs(directions).max(axis=1, keepdims=True)
    normal = directions[:count] * 10.0 ** rng.uniform(-300, -4, size=(count, 1))
    subnormal = directions[count:] * 10.0 ** rng.uniform(-323.3, -307.7, size=(count, 1))
    lever = float(np.abs(geometry.torque_map).max())
    floor_Nm = allocator.n_engines * (lever + 2.0) * 2.0**-1074
    allocator.allocate(normal[0])
    wall, relative, rescued = [], [], 0
    for torque in normal:
        start = time.perf_counter()
        result = allocator.allocate(torque)
        wall.append(time.perf_counter() - start)
        rescued += result.solver.endswith("+highs")
        error = float(np.abs(result.torque_Nm - torque).max() / np.abs(torque).max())
        relative.append(error if result.feasible else math.inf)
    in_floors = []
    for torque in subnormal:
        result = allocator.allocate(torque)
        rescued += result.solver.endswith("+highs")
        error = float(np.abs(result.torque_Nm - torque).max())
        in_floors.append(error / floor_Nm if result.feasible else math.inf)
    return {
        "demands": 2 * count,
        **percentiles_us(wall),
        "feasible_fraction": float(np.mean(np.isfinite(relative + in_floors))),
        "max_relative_error_normal": float(np.max(relative)),
        "max_error_subnormal_in_floors": float(np.max(in_floors)),
        "floor_Nm": floor_Nm,
        "highs_fallbacks": rescued,
    }


def series_benchmark(problem, geometry, authority: dict[str, float], steps: int, repeats: int):
    """Per-step time of allocate_series against a loop of allocate over one smooth history."""
    torques = smooth_history(authority, steps)
    per_step_s, polytope_s, point_solves = [], [], []
    for _ in range(repeats):
        allocator = Allocator.from_problem(problem, geometry)
        start = time.perf_counter()
        allocator.authority_polytope()
        polytope_s.append(time.perf_counter() - start)
        start = time.perf_counter()
        series = allocator.allocate_series(torques)
        per_step_s.append((time.perf_counter() - start) / steps)
        point_solves.append(series.point_solves)
    allocator = Allocator.from_problem(problem, geometry)
    allocator.allocate(torques[0])  # first call sets up lazily built workspaces
    wall, _ = time_calls(allocator.allocate, torques)
    series_median = float(np.median(per_step_s))
    loop_median = float(np.median(wall))
    return {
        "steps": steps,
        "repeats": repeats,
        "saturated_fraction": float(np.mean(series.scale < 1.0)),
        "point_solves": int(np.median(point_solves)),
        "series_per_step_median_us": series_median * US_PER_S,
        "polytope_median_ms": float(np.median(polytope_s)) * 1e3,
        "allocate_loop_per_step_median_us": loop_median * US_PER_S,
        "allocate_loop_per_step_mean_us": float(np.mean(wall)) * US_PER_S,
        "speed_up_median": loop_median / series_median,
    }


def engines_scaling(problem, rng: np.random.Generator, calls: int) -> dict:
    """Median ``allocate`` time (DAQP) with the paper's 24 engines and with 48, in one run.

    The 48-engine swarm is the paper's debris with eight CubeSats on a grid on each face
    (``face_grid``, main engines only); demands are 0.9 of each swarm's weakest axis.
    """
    data = tomllib.loads(default_problem_path().read_text())
    data["cubesat_layout"] |= {"kind": "face_grid", "per_face": 8}
    timings = {}
    for label, swarm in (("24", problem), ("48", problem_from_dict(data, "48 engines"))):
        allocator = Allocator.from_problem(swarm)
        torques = demands(rng, calls, min(allocator.torque_authority().values()), 0.9)
        allocator.allocate(torques[0])
        wall, _ = time_calls(allocator.allocate, torques)
        timings[label] = {"engines": allocator.n_engines, **percentiles_us(wall)}
    timings["ratio_48_to_24"] = timings["48"]["median_us"] / timings["24"]["median_us"]
    return timings


OPTIONS = {
    "--calls": Setting(2000, 300, "demands per back-end and case (2000)"),
    "--solvers": {"default": None, "help": "comma-separated (default: all)"},
    "--series-steps": Setting(12_000, 2000, "steps of the allocate_series history (12,000)"),
    "--series-repeats": Setting(5, 3, "allocate_series runs (5)"),
}


def main() -> None:
    args, recording, settings = start_benchmark(
        "allocation",
        __doc__.splitlines()[0],
        "300 demands, 2000 steps, 3 series runs",
        OPTIONS,
        libraries=("daqp", "osqp", "qpsolvers", "clarabel"),
    )

    problem = load_problem()
    geometry = build_geometry(problem)
    rng = np.random.default_rng(SEED)
    reference = Allocator.from_problem(problem, geometry)
    authority = reference.torque_authority()
    scale_Nm = min(authority.values())
    feasible = demands(rng, args.calls, scale_Nm, 0.9)
    saturating = demands(rng, args.calls, scale_Nm, 20.0)
    solvers = args.solvers.split(",") if args.solvers else list(available_solvers())

    baseline = PseudoInverseAllocator(reference)
    base_wall, _ = time_calls(baseline.allocate, feasible)
    base_median = float(np.median(base_wall))
    per_call: dict[str, dict] = {
        "pseudo_inverse": {"feasible": percentiles_us(base_wall), "ratio_to_pseudo_inverse": 1.0}
    }

    for solver in solvers:
        allocator = Allocator.from_problem(problem, geometry, solver=solver)
        calls = args.calls if solver in ("daqp", "osqp") else max(50, args.calls // 20)
        allocator.allocate(feasible[0])  # first call sets up lazily built workspaces
        entry: dict = {}
        for case, torques in (("feasible", feasible[:calls]), ("saturating", saturating[:calls])):
            wall, backend = time_calls(allocator.allocate, torques)
            entry[case] = {
                **percentiles_us(wall),
                "backend_" + "median_us": float(np.median(backend) * US_PER_S),
            }
        entry["ratio_to_pseudo_inverse"] = entry["feasible"]["median_us"] / (base_median * US_PER_S)
        entry["calls"] = calls
        per_call[solver] = entry

    mixed = np.concatenate([feasible[: args.calls // 2], saturating[: args.calls // 2]])
    rng.shuffle(mixed)
    batch = Allocator.from_problem(problem, geometry).allocate_batch(mixed)
    limits = reference.max_thrust_N

    n_quality = min(200, args.calls)
    lp_max = np.array([lp_largest_torque(geometry, limits, t) for t in saturating[:n_quality]])
    saturation: dict[str, dict] = {}
    methods = {"pseudo_inverse": baseline.allocate}
    for solver in ("daqp", "osqp"):
        if solver in solvers:
            methods[solver] = Allocator.from_problem(problem, geometry, solver=solver).allocate
    for name, allocate in methods.items():
        fractions, angles = [], []
        for torque, best in zip(saturating[:n_quality], lp_max, strict=True):
            result = allocate(torque)
            along = float(result.torque_Nm @ torque / np.linalg.norm(torque))
            fractions.append(along / best)
            cross = float(np.linalg.norm(np.cross(result.torque_Nm, torque)))
            angles.append(math.atan2(cross, float(result.torque_Nm @ torque)))
        saturation[name] = {
            "fraction_of_lp_max_median": float(np.median(fractions)),
            "fraction_of_lp_max_min": float(np.min(fractions)),
            "angle_error_max_rad": float(np.max(angles)),
        }

    tiny = tiny_benchmark(problem, geometry, rng, min(500, args.calls))
    series = series_benchmark(problem, geometry, authority, args.series_steps, args.series_repeats)
    scaling = engines_scaling(problem, rng, args.calls)

    recording.finish(
        settings,
        {
            "problem": problem.name,
            "engines": reference.n_engines,
            "seed": SEED,
            "solvers": solvers,
            "per_call": per_call,
            "batch": {
                "demands": len(mixed),
                "solves_per_s": len(mixed) / batch.wall_time_s,
                "wall_time_s": batch.wall_time_s,
            },
            "saturation": saturation,
            "tiny": tiny,
            "series": series,
            "engines_scaling": scaling,
        },
    )


if __name__ == "__main__":
    main()
